-- Family 13: a vector terminal (electrical_vector) and composite branch quantities.
-- A 1 V step at node a feeds three capacitors t(1..3) (1 uF each, one composite branch to ground)
-- through 1, 2 and 3 kOhm:   vc(k)(t) = 1 - exp(-t/(k ms)),  k = 1, 2, 3.
library ieee;
use ieee.electrical_systems.all;

entity vector_rc_tb is
  generic (c : capacitance := 1.0e-6);
end entity vector_rc_tb;

architecture behav of vector_rc_tb is
  terminal a : electrical;
  terminal t : electrical_vector(1 to 3);
  quantity vs across isrc through a to electrical_ref;
  quantity vc across ic through t to electrical_ref;       -- real_vector(1 to 3) each
  quantity vr1 across ir1 through a to t(1);
  quantity vr2 across ir2 through a to t(2);
  quantity vr3 across ir3 through a to t(3);
begin
  if domain = quiescent_domain use
    vs == 0.0;
  else
    vs == 1.0;
  end use;
  vr1 == 1.0e3 * ir1;
  vr2 == 2.0e3 * ir2;
  vr3 == 3.0e3 * ir3;
  ic(1) == c * vc(1)'dot;
  ic(2) == c * vc(2)'dot;
  ic(3) == c * vc(3)'dot;
end architecture behav;
