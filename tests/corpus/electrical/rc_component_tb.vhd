-- Family 5: component declarations and component instantiation with generic maps.
-- A 2 V step source, a 2 kOhm resistor and a 0.5 uF capacitor as separate entities (tau = 1 ms):
--   v(out) = 2*(1 - exp(-t/1 ms)),  current of the resistor = 1 mA*exp(-t/1 ms).
library ieee;
use ieee.electrical_systems.all;

entity cmp_step_source is
  generic (level : voltage := 1.0);
  port (terminal p, m : electrical);
end entity cmp_step_source;

architecture ideal of cmp_step_source is
  quantity v across i through p to m;
begin
  if domain = quiescent_domain use
    v == 0.0;
  else
    v == level;
  end use;
end architecture ideal;

library ieee;
use ieee.electrical_systems.all;

entity cmp_resistor is
  generic (r : resistance := 1.0e3);
  port (terminal p, m : electrical);
end entity cmp_resistor;

architecture ideal of cmp_resistor is
  quantity v across i through p to m;
begin
  v == r * i;
end architecture ideal;

library ieee;
use ieee.electrical_systems.all;

entity cmp_capacitor is
  generic (c : capacitance := 1.0e-6);
  port (terminal p, m : electrical);
end entity cmp_capacitor;

architecture ideal of cmp_capacitor is
  quantity v across i through p to m;
begin
  i == c * v'dot;
end architecture ideal;

library ieee;
use ieee.electrical_systems.all;

entity rc_component_tb is
end entity rc_component_tb;

architecture structural of rc_component_tb is
  component cmp_step_source is
    generic (level : voltage := 1.0);
    port (terminal p, m : electrical);
  end component cmp_step_source;
  component cmp_resistor is
    generic (r : resistance := 1.0e3);
    port (terminal p, m : electrical);
  end component cmp_resistor;
  component cmp_capacitor is
    generic (c : capacitance := 1.0e-6);
    port (terminal p, m : electrical);
  end component cmp_capacitor;
  terminal n_in, n_out : electrical;
begin
  src : cmp_step_source generic map (level => 2.0) port map (p => n_in, m => electrical_ref);
  r1 : cmp_resistor generic map (2.0e3) port map (n_in, n_out);
  c1 : cmp_capacitor generic map (c => 0.5e-6) port map (p => n_out, m => electrical_ref);
end architecture structural;
