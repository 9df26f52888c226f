-- Family 17: signals of a real subtype (IEEE electrical_systems' resistance) and a real signal set by a conditional
-- signal assignment on a bit (`v_in <= v_high when d = '1' else v_low;`), as textbook sources write them.
--   d: '0' until 1 ms, then '1';  r = 100 Ohm, 200 Ohm from 1 ms;  v_in = 1 V, 5 V from 1 ms;
--   the divider i = v_in / (r + 100 Ohm): 5 mA, then 5/300 A.
library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;

entity real_subtype_signal_tb is
  generic (v_low : voltage := 1.0;    -- [V]
           v_high : voltage := 5.0);  -- [V]
end entity real_subtype_signal_tb;

architecture behav of real_subtype_signal_tb is
  signal r : resistance := 100.0;
  signal d : bit := '0';
  signal v_in : voltage := 0.0;
  quantity v, i : real;
begin
  stimulus: process
  begin
    wait for 1 ms;
    d <= '1';
    r <= 200.0;
    wait;
  end process stimulus;

  v_in <= v_high when d = '1' else v_low;
  v == v_in;
  i == v / (r + 100.0);
end architecture behav;
