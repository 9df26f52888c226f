-- Family 14: conditional and selected concurrent signal assignments (IEEE 1076 11.6: each is the process that
-- runs its if or case whenever a signal it reads changes), a clock made by a concurrent assignment to itself.
-- clk toggles every 1 ms from '0' (clk <= not clk after 1 ms); sel = floor(t / 1 ms) (a stimulus process);
--   gate = 3 while clk = '1' (t in [1, 2), [3, 4) ms), -1 otherwise;
--   level = 1 for sel = 0, 2 for sel = 1 or 2, 0.5 from sel = 3 on (others);
--   g == gate, y == level, z' = (g - z)/tau with tau = 1 ms, z(0) = -1 (the quiescent point sees gate = -1).
library ieee;
use ieee.math_real.all;

entity concurrent_assign_tb is
  generic (tau : real := 1.0e-3);   -- tau [s]
end entity concurrent_assign_tb;

architecture behav of concurrent_assign_tb is
  signal clk : bit := '0';
  signal sel : integer := 0;
  signal gate, level : real := 0.0;
  quantity g, y, z : real;
begin
  clk <= not clk after 1 ms;

  count : process is
  begin
    wait for 1 ms;
    sel <= sel + 1;
  end process count;

  gate <= 3.0 when clk = '1' else -1.0;

  with sel select
    level <= 1.0 when 0,
             2.0 when 1 | 2,
             0.5 when others;

  g == gate;
  y == level;
  break on gate;
  z'dot == (g - z) / tau;
end architecture behav;
