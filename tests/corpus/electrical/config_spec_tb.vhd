-- Family 15: configuration specification binding a component to an entity/architecture.
-- Entity cfg_res has architectures doubled (v = 2*r*i) and plain (v = r*i); plain is analysed last and is
-- therefore the default binding. The bench binds every instance of component resistor to
-- entity work.cfg_res(doubled): the 1 kOhm resistor acts as 2 kOhm with c = 1 uF (tau = 2 ms):
--   vc(t) = 1 - exp(-t/2 ms)
library ieee;
use ieee.electrical_systems.all;

entity cfg_res is
  generic (r : resistance := 1.0e3);
  port (terminal p, m : electrical);
end entity cfg_res;

architecture doubled of cfg_res is
  quantity v across i through p to m;
begin
  v == 2.0 * r * i;
end architecture doubled;

architecture plain of cfg_res is
  quantity v across i through p to m;
begin
  v == r * i;
end architecture plain;

library ieee;
use ieee.electrical_systems.all;

entity config_spec_tb is
end entity config_spec_tb;

architecture structural of config_spec_tb is
  component resistor is
    generic (r : resistance := 1.0e3);
    port (terminal p, m : electrical);
  end component resistor;
  for all : resistor use entity work.cfg_res(doubled);
  terminal a, b : electrical;
  quantity vs across isrc through a to electrical_ref;
  quantity vc across ic through b to electrical_ref;
begin
  if domain = quiescent_domain use
    vs == 0.0;
  else
    vs == 1.0;
  end use;
  ic == 1.0e-6 * vc'dot;
  r1 : resistor generic map (r => 1.0e3) port map (p => a, m => b);
end architecture structural;
