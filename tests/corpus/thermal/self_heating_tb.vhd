-- Family 6: electro-thermal self-heating resistor (electrical and thermal natures coupled).
-- u = 10 V across r(T) = r0*(1 + alpha*T), r0 = 10 Ohm, alpha = 0.004 1/K, T = temperature rise of a body
-- cth = 2 J/K with rth = 5 K/W to ambient:   cth*T' = u**2/r(T) - T/rth.   Reference: SciPy solve_ivp;
-- also i = u/r(T).
library ieee;
use ieee.electrical_systems.all;
use ieee.thermal_systems.all;

entity self_heating_tb is
  generic (u : voltage := 10.0; r0 : resistance := 10.0; alpha : real := 0.004;   -- [1/K]
           rth : thermal_resistance := 5.0; cth : thermal_capacitance := 2.0);
end entity self_heating_tb;

architecture behav of self_heating_tb is
  terminal p : electrical;
  terminal hot : thermal;
  quantity vs across isrc through p to electrical_ref;
  quantity v across i through p to electrical_ref;
  quantity q_heat through thermal_ref to hot;          -- the resistor's dissipation heats the body
  quantity temp across q_c through hot to thermal_ref;
  quantity t_r across q_r through hot to thermal_ref;
begin
  vs == u;
  v == r0 * (1.0 + alpha * temp) * i;
  q_heat == v * i;
  q_c == cth * temp'dot;
  t_r == rth * q_r;
  break temp => 0.0;
end architecture behav;
