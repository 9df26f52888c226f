-- Family 8: signal'ramp(tr, tf). A process sets s: 0 -> 2 at 1 ms, 2 -> 0 at 4 ms; s'ramp(1 ms, 2 ms):
--   q = 0 (t < 1 ms), 2*(t - 1 ms)/1 ms (1..2 ms), 2 (2..4 ms), 2 - 2*(t - 4 ms)/2 ms (4..6 ms), 0 after 6 ms
library ieee;
use ieee.math_real.all;

entity ramp_tb is
end entity ramp_tb;

architecture behav of ramp_tb is
  signal s : real := 0.0;
  quantity q : real;
begin
  stimulus : process is
  begin
    wait for 1 ms;
    s <= 2.0;
    wait for 3 ms;
    s <= 0.0;
    wait;
  end process stimulus;

  q == s'ramp(1.0e-3, 2.0e-3);
end architecture behav;
