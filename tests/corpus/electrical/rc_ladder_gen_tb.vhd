-- Family 12: for-generate chain of RC ladder sections (entity instantiation inside the generate), nodes in an
-- array terminal of a locally declared array nature.
-- Three sections r = 1 kOhm, c = 1 uF driven by a 1 V step. With x_k the capacitor voltages (x_0 = 1):
--   c*x_k' = (x_{k-1} - x_k)/r - (x_k - x_{k+1})/r  (no x_4 term for the last section)
-- Reference: SciPy solve_ivp of this ODE.
library ieee;
use ieee.electrical_systems.all;

entity ladder_section is
  generic (r : resistance := 1.0e3; c : capacitance := 1.0e-6);
  port (terminal left, right : electrical);
end entity ladder_section;

architecture behav of ladder_section is
  quantity vr across ir through left to right;
  quantity vc across ic through right to electrical_ref;
begin
  vr == r * ir;
  ic == c * vc'dot;
end architecture behav;

library ieee;
use ieee.electrical_systems.all;

entity rc_ladder_gen_tb is
  generic (sections : integer := 3);
end entity rc_ladder_gen_tb;

architecture structural of rc_ladder_gen_tb is
  nature node_array is array (natural range <>) of electrical;
  terminal n : node_array(0 to sections);
  quantity vs across isrc through n(0) to electrical_ref;
  quantity vout across n(sections) to electrical_ref;
begin
  if domain = quiescent_domain use
    vs == 0.0;
  else
    vs == 1.0;
  end use;
  chain : for k in 1 to sections generate
    sec : entity work.ladder_section(behav)
      generic map (r => 1.0e3, c => 1.0e-6)
      port map (left => n(k - 1), right => n(k));
  end generate chain;
end architecture structural;
