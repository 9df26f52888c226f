-- Family 8: 'delayed(T), T = 1 ms, of x = sin(2*pi*200*t):
--   y(t) = sin(2*pi*200*(t - T)) for t >= T,  y(t) = x(0) = 0 for t < T
library ieee;
use ieee.math_real.all;

entity delayed_tb is
  generic (freq : real := 200.0;   -- [Hz]
           delay : real := 1.0e-3);   -- [s]
end entity delayed_tb;

architecture behav of delayed_tb is
  quantity x, y : real;
begin
  x == sin(math_2_pi * freq * now);
  y == x'delayed(delay);
end architecture behav;
