-- Family 2: second-order ODE written with 'dot'dot, unit step input from t = 0.
--   x'' + 2*zeta*w*x' + w**2*x = w**2*u,  w = 100 rad/s, zeta = 0.3, x(0) = x'(0) = 0:
--   x(t) = 1 - exp(-zeta*w*t)*(cos(wd*t) + zeta*w/wd*sin(wd*t)),  wd = w*sqrt(1 - zeta**2)
library ieee;
use ieee.math_real.all;

entity dotdot_step_tb is
  generic (w : real := 100.0;   -- [rad/s]
           zeta : real := 0.3);
end entity dotdot_step_tb;

architecture behav of dotdot_step_tb is
  quantity u, x : real;
begin
  if domain = quiescent_domain use
    u == 0.0;
  else
    u == 1.0;
  end use;
  x'dot'dot == w * w * (u - x) - 2.0 * zeta * w * x'dot;
end architecture behav;
