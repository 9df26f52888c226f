-- IEEE_PROPOSED thermal natures, family 6/7: Newton cooling from a break-list initial temperature rise.
-- A body cth = 4 J/K, 60 K above ambient at t = 0, cools through rth = 0.5 K/W (tau = 2 s):
--   T(t) = 60*exp(-t/2 s)
library ieee_proposed;
use ieee_proposed.thermal_systems.all;

entity thermal_proposed_tb is
  generic (rth : thermal_resistance := 0.5; cth : thermal_capacitance := 4.0; t0 : temperature := 60.0);
end entity thermal_proposed_tb;

architecture behav of thermal_proposed_tb is
  terminal body_node : thermal;
  quantity temp across q_c through body_node to thermal_ref;
  quantity t_r across q_r through body_node to thermal_ref;
begin
  q_c == cth * temp'dot;
  t_r == rth * q_r;
  break temp => t0;
end architecture behav;
