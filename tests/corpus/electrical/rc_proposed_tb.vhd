-- IEEE_PROPOSED natures, family 1 and 7: RC discharge from a break-list initial value.
-- c = 2 uF starts at 3 V (break vc => 3.0) and discharges into r = 500 Ohm (tau = 1 ms):
--   vc(t) = 3*exp(-t/1 ms),  ir(t) = 6 mA*exp(-t/1 ms)
library ieee_proposed;
use ieee_proposed.electrical_systems.all;

entity rc_proposed_tb is
  generic (v0 : voltage := 3.0; r : resistance := 500.0; c : capacitance := 2.0e-6);
end entity rc_proposed_tb;

architecture behav of rc_proposed_tb is
  terminal n : electrical;
  quantity vc across ic through n to electrical_ref;
  quantity vr across ir through n to electrical_ref;
begin
  ic == c * vc'dot;
  vr == r * ir;
  break vc => v0;
end architecture behav;
