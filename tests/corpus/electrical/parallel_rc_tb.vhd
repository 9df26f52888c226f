-- Family 14: several through quantities on one branch (quantity v across ir, icap through a).
-- A 1 mA current step into node a, where r = 1 kOhm and c = 1 uF share one branch:
--   v(t) = 1*(1 - exp(-t/1 ms)),  ir = v/r,  icap = 1 mA*exp(-t/1 ms).
library ieee;
use ieee.electrical_systems.all;

entity parallel_rc_tb is
  generic (i0 : current := 1.0e-3; r : resistance := 1.0e3; c : capacitance := 1.0e-6);
end entity parallel_rc_tb;

architecture behav of parallel_rc_tb is
  terminal a : electrical;
  quantity isrc through a to electrical_ref;        -- current source: negative = current into a
  quantity v across ir, icap through a to electrical_ref;
begin
  if domain = quiescent_domain use
    isrc == 0.0;
  else
    isrc == -i0;
  end use;
  ir == v / r;
  icap == c * v'dot;
end architecture behav;
