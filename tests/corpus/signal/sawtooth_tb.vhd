-- Families 7 and 9: 'break x => 0.0 on s' with a clock process toggling a boolean signal every 1 ms.
-- x' = 1000 1/s from x(0) = 0 (break list at t = 0), reset to 0 at every event on clk (t = 1, 2, 3, 4 ms):
--   x(t) = 1000*(t mod 1 ms)
library ieee;
use ieee.math_real.all;

entity sawtooth_tb is
  generic (rate : real := 1.0e3);   -- [1/s]
end entity sawtooth_tb;

architecture behav of sawtooth_tb is
  signal clk : boolean := false;
  quantity x : real;
begin
  clock : process is
  begin
    wait for 1 ms;
    clk <= not clk;
  end process clock;

  x'dot == rate;
  break x => 0.0;
  break x => 0.0 on clk;
end architecture behav;
