-- Family 3: simultaneous case (nested in a simultaneous if) selecting the source level by an integer generic.
-- mode = 2 selects 2 V; the RC (1 kOhm, 1 uF) charges to it:
--   vc(t) = 2*(1 - exp(-t/1 ms))
library ieee;
use ieee.electrical_systems.all;

entity mode_case_tb is
  generic (mode : integer := 2; r : resistance := 1.0e3; c : capacitance := 1.0e-6);
end entity mode_case_tb;

architecture behav of mode_case_tb is
  terminal a, b : electrical;
  quantity vs across isrc through a to electrical_ref;
  quantity vr across ir through a to b;
  quantity vc across ic through b to electrical_ref;
begin
  if domain = quiescent_domain use
    vs == 0.0;
  else
    case mode use
      when 0 =>
        vs == 0.0;
      when 1 =>
        vs == 1.0;
      when 2 | 3 =>
        vs == 2.0;
      when others =>
        vs == 5.0;
    end case;
  end use;
  vr == r * ir;
  ic == c * vc'dot;
end architecture behav;
