-- Family 7: break list at t = 0 on a free quantity; a second quantity reads it algebraically.
--   y' = -y/tau, break y => 2.0, tau = 1 ms:   y(t) = 2*exp(-t/tau),  z = y**2 = 4*exp(-2*t/tau)
library ieee;
use ieee.math_real.all;

entity break_decay_tb is
  generic (tau : real := 1.0e-3;   -- [s]
           y0 : real := 2.0);
end entity break_decay_tb;

architecture behav of break_decay_tb is
  quantity y, z : real;
begin
  y'dot == -y / tau;
  z == y ** 2;
  break y => y0;
end architecture behav;
