-- Family 5/6: two-node thermal network (junction and case) built from thermal component entities.
-- p = 5 W into the junction (cj = 1 J/K); rjc = 1 K/W to the case (cc = 10 J/K); rca = 2 K/W to ambient:
--   cj*tj' = p - (tj - tc)/rjc,   cc*tc' = (tj - tc)/rjc - tc/rca.   Reference: SciPy solve_ivp.
library ieee;
use ieee.thermal_systems.all;

entity th_capacitor is
  generic (cth : thermal_capacitance := 1.0);
  port (terminal p : thermal);
end entity th_capacitor;

architecture ideal of th_capacitor is
  quantity t across q through p to thermal_ref;
begin
  q == cth * t'dot;
end architecture ideal;

library ieee;
use ieee.thermal_systems.all;

entity th_resistor is
  generic (rth : thermal_resistance := 1.0);
  port (terminal p, m : thermal);
end entity th_resistor;

architecture ideal of th_resistor is
  quantity dt across q through p to m;
begin
  dt == rth * q;
end architecture ideal;

library ieee;
use ieee.thermal_systems.all;

entity th_source is
  generic (p_heat : heat_flow := 1.0);
  port (terminal p : thermal);
end entity th_source;

architecture step of th_source is
  quantity q through thermal_ref to p;
begin
  if domain = quiescent_domain use
    q == 0.0;
  else
    q == p_heat;
  end use;
end architecture step;

library ieee;
use ieee.thermal_systems.all;

entity thermal_two_node_tb is
end entity thermal_two_node_tb;

architecture structural of thermal_two_node_tb is
  terminal junction, case_node : thermal;
  quantity tj across junction to thermal_ref;
  quantity tc across case_node to thermal_ref;
begin
  heat : entity work.th_source(step) generic map (p_heat => 5.0) port map (p => junction);
  c_j : entity work.th_capacitor(ideal) generic map (cth => 1.0) port map (p => junction);
  r_jc : entity work.th_resistor(ideal) generic map (rth => 1.0) port map (p => junction, m => case_node);
  c_c : entity work.th_capacitor(ideal) generic map (cth => 10.0) port map (p => case_node);
  r_ca : entity work.th_resistor(ideal) generic map (rth => 2.0) port map (p => case_node, m => thermal_ref);
end architecture structural;
