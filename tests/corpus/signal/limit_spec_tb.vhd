-- Family 15: a step limit specification on a quantity (limit y : real with 1.0e-4), which bounds the step and
-- leaves the solution alone.  y' = (u - y)/tau, unit step, tau = 1 ms:   y(t) = 1 - exp(-t/tau)
library ieee;
use ieee.math_real.all;

entity limit_spec_tb is
  generic (tau : real := 1.0e-3);   -- [s]
end entity limit_spec_tb;

architecture behav of limit_spec_tb is
  quantity u, y : real;
  limit y : real with 1.0e-4;
begin
  if domain = quiescent_domain use
    u == 0.0;
  else
    u == 1.0;
  end use;
  y'dot == (u - y) / tau;
end architecture behav;
