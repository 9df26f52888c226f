-- Family 5: entity instantiation choosing between several architectures of one entity.
-- arch_res(ideal): v = r*i;  arch_res(scaled): v = factor*r*i. The bench uses r_top = ideal 1 kOhm and
-- r_low = scaled 1 kOhm with factor 3 (3 kOhm), and c = 1 uF at the middle node. For a 4 V step:
--   k = 3/(1 + 3) = 0.75, tau = (1 kOhm || 3 kOhm)*c = 0.75 ms,  vm(t) = 3*(1 - exp(-t/0.75 ms)).
library ieee;
use ieee.electrical_systems.all;

entity arch_res is
  generic (r : resistance := 1.0e3; factor : real := 1.0);
  port (terminal p, m : electrical);
end entity arch_res;

architecture ideal of arch_res is
  quantity v across i through p to m;
begin
  v == r * i;
end architecture ideal;

architecture scaled of arch_res is
  quantity v across i through p to m;
begin
  v == factor * r * i;
end architecture scaled;

library ieee;
use ieee.electrical_systems.all;

entity divider_arch_tb is
  generic (u : voltage := 4.0; c : capacitance := 1.0e-6);
end entity divider_arch_tb;

architecture structural of divider_arch_tb is
  terminal top, mid : electrical;
  quantity vs across isrc through top to electrical_ref;
  quantity vm across icap through mid to electrical_ref;
begin
  if domain = quiescent_domain use
    vs == 0.0;
  else
    vs == u;
  end use;
  icap == c * vm'dot;
  r_top : entity work.arch_res(ideal) generic map (r => 1.0e3) port map (p => top, m => mid);
  r_low : entity work.arch_res(scaled) generic map (r => 1.0e3, factor => 3.0) port map (p => mid, m => electrical_ref);
end architecture structural;
