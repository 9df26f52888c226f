-- Families 8 and 9: 'slew(rise, fall) of a quantity driven by a signal that a process steps 0 -> 1 at 1 ms and
-- 1 -> 0 at 3 ms (break on the signal). Rising slope 1000 1/s, falling slope -500 1/s:
--   y = 0 (t < 1 ms), 1000*(t - 1 ms) (1..2 ms), 1 (2..3 ms), 1 - 500*(t - 3 ms) (3..5 ms), 0 after 5 ms
library ieee;
use ieee.math_real.all;

entity slew_tb is
end entity slew_tb;

architecture behav of slew_tb is
  signal level : real := 0.0;
  quantity u, y : real;
begin
  stimulus : process is
  begin
    wait for 1 ms;
    level <= 1.0;
    wait for 2 ms;
    level <= 0.0;
    wait;
  end process stimulus;

  u == level;
  break on level;
  y == u'slew(1000.0, -500.0);
end architecture behav;
