-- Family 2/6: nonlinear damped pendulum (math_real sin), released at 1 rad.
--   theta'' = -(g/len)*sin(theta) - c*theta',  g = 9.81, len = 1 m, c = 0.5 1/s
-- Reference: SciPy solve_ivp.
library ieee;
use ieee.mechanical_systems.all;
use ieee.math_real.all;

entity pendulum_tb is
  generic (g : acceleration := 9.81; len : displacement := 1.0; c : real := 0.5; theta0 : angle := 1.0);
end entity pendulum_tb;

architecture behav of pendulum_tb is
  quantity theta : angle;
  quantity w : angular_velocity;
begin
  theta'dot == w;
  w'dot == -(g / len) * sin(theta) - c * w;
  break theta => theta0, w => 0.0;
end architecture behav;
