-- Family 2: 'integ. A harmonic oscillator written with two integrators (w = 1000 rad/s):
--   a = 1 - w*integral(b),  b = w*integral(a)   =>   a(t) = cos(w*t),  b(t) = sin(w*t)
-- ('integ is 0 at t = 0, so a(0) = 1, b(0) = 0.)
library ieee;
use ieee.math_real.all;

entity integ_oscillator_tb is
  generic (w : real := 1.0e3);   -- [rad/s]
end entity integ_oscillator_tb;

architecture behav of integ_oscillator_tb is
  quantity a, b : real;
begin
  a == 1.0 - w * b'integ;
  b == w * a'integ;
end architecture behav;
