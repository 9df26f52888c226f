-- Family 6: thermal RC (temperature across, heat_flow through).
-- A 10 W heat source into a body of cth = 5 J/K tied to ambient (thermal_ref) by rth = 2 K/W (tau = 10 s):
--   temperature rise T(t) = 20*(1 - exp(-t/10 s)),  heat flow to ambient q_r = T/rth
library ieee;
use ieee.thermal_systems.all;

entity thermal_rc_tb is
  generic (p_heat : heat_flow := 10.0; rth : thermal_resistance := 2.0; cth : thermal_capacitance := 5.0);
end entity thermal_rc_tb;

architecture behav of thermal_rc_tb is
  terminal body_node : thermal;
  quantity t_src through thermal_ref to body_node;                 -- the heat source
  quantity temp across q_c through body_node to thermal_ref;
  quantity t_r across q_r through body_node to thermal_ref;
begin
  if domain = quiescent_domain use
    t_src == 0.0;
  else
    t_src == p_heat;
  end use;
  q_c == cth * temp'dot;
  t_r == rth * q_r;
end architecture behav;
