-- Family 4/6: a thermal nature declared in a package of the design's own (temperature across, heat_flow
-- through, as in IEEE 1076.1.1 THERMAL_SYSTEMS), used for a die-on-heat-sink network.
-- p = 20 W into the die (c1 = 2 J/K); r12 = 0.5 K/W to the sink (c2 = 40 J/K); r2a = 1.5 K/W to ambient:
--   c1*t1' = p - (t1 - t2)/r12,   c2*t2' = (t1 - t2)/r12 - t2/r2a.   Reference: SciPy solve_ivp.
package my_thermal is
  subtype temperature is real tolerance "default_temperature";                 -- [K]
  subtype heat_flow is real tolerance "default_heat_flow";                     -- [W]
  subtype thermal_capacitance is real tolerance "default_thermal_capacitance"; -- [J/K]
  subtype thermal_resistance is real tolerance "default_thermal_resistance";   -- [K/W]
  nature thermal is temperature across heat_flow through thermal_ref reference;
end package my_thermal;

use work.my_thermal.all;

entity thermal_local_tb is
  generic (p_heat : heat_flow := 20.0; c1 : thermal_capacitance := 2.0; r12 : thermal_resistance := 0.5;
           c2 : thermal_capacitance := 40.0; r2a : thermal_resistance := 1.5);
end entity thermal_local_tb;

architecture behav of thermal_local_tb is
  terminal die, sink : thermal;
  quantity q_src through thermal_ref to die;
  quantity t_die across q_c1 through die to thermal_ref;
  quantity dt12 across q12 through die to sink;
  quantity t_sink across q_c2 through sink to thermal_ref;
  quantity t_r2a across q2a through sink to thermal_ref;
begin
  if domain = quiescent_domain use
    q_src == 0.0;
  else
    q_src == p_heat;
  end use;
  q_c1 == c1 * t_die'dot;
  dt12 == r12 * q12;
  q_c2 == c2 * t_sink'dot;
  t_r2a == r2a * q2a;
end architecture behav;
