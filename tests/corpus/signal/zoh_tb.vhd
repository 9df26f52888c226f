-- Family 8: 'zoh(T), sample-and-hold of x = sin(2*pi*100*t) every T = 0.5 ms (first sample at t = 0):
--   y(t) = sin(2*pi*100*floor(t/T)*T)
library ieee;
use ieee.math_real.all;

entity zoh_tb is
  generic (freq : real := 100.0;   -- [Hz]
           period : real := 0.5e-3);   -- [s]
end entity zoh_tb;

architecture behav of zoh_tb is
  quantity x, y : real;
begin
  x == sin(math_2_pi * freq * now);
  y == x'zoh(period);
end architecture behav;
