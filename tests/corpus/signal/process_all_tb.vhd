-- Family 14: `process (all)` (VHDL-2008) is sensitive to every signal it reads and to the 'above it reads, not to
-- its own variable nor to a quantity it reads: y = a + 10*b + (100 when x > 2.5), with x = t/1 ms and a stimulus
-- a = 1 from 1 ms, b = 2 from 2 ms, a = 3 from 3 ms, so
--   y = 0 on [0, 1) ms, 1 on [1, 2), 21 on [2, 2.5), 121 on [2.5, 3), 123 from 3 ms;
--   w == y, and yl'dot == (w - yl)/tau with tau = 1 ms follows it.
library ieee;
use ieee.math_real.all;

entity process_all_tb is
  generic (tau : real := 1.0e-3);   -- tau [s]
end entity process_all_tb;

architecture behav of process_all_tb is
  signal a, b, y : real := 0.0;
  quantity x, w, yl : real;
begin
  stimulus : process is
  begin
    wait for 1 ms;
    a <= 1.0;
    wait for 1 ms;
    b <= 2.0;
    wait for 1 ms;
    a <= 3.0;
    wait;
  end process stimulus;

  sum : process (all) is
    variable s : real := 0.0;
  begin
    s := a + 10.0 * b;
    if x'above(2.5) then
      s := s + 100.0;
    end if;
    y <= s;
  end process sum;

  x == now / tau;
  w == y;
  break on y;
  yl'dot == (w - yl) / tau;
end architecture behav;
