-- Families 1 and 7: LC oscillator started by a break list at t = 0.
-- l = 1 mH, c = 1 uF, w = 1/sqrt(l*c) = 31622.78 rad/s. The quiescent point takes vc = 1 V and il = 0 A
-- (break list) instead of vc'dot = 0 and il'dot = 0:
--   vc(t) = cos(w*t),  il(t) = c*w*sin(w*t)   (il flows from the node through the inductor to ground)
library ieee;
use ieee.electrical_systems.all;

entity lc_tank_tb is
  generic (l : inductance := 1.0e-3; c : capacitance := 1.0e-6);
end entity lc_tank_tb;

architecture behav of lc_tank_tb is
  terminal n : electrical;
  quantity vc across ic through n to electrical_ref;
  quantity vl across il through n to electrical_ref;
begin
  ic == c * vc'dot;
  vl == l * il'dot;
  break vc => 1.0, il => 0.0;
end architecture behav;
