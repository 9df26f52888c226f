-- Family 15: a break list whose element selects a derivative (`break x'dot => 0.5;`: at the quiescent point
-- x'dot takes 0.5 instead of 0, 1076.1) and a tolerance aspect given by an attribute (`velocity'tolerance`).
-- x'dot == k*(1 - x) with k = 2 /s: at the quiescent point 0.5 = k*(1 - x) gives x(0) = 0.75; then
--   x(t) = 1 - 0.25*exp(-k*t),  v = x'dot = 0.5*exp(-k*t).
library ieee;
use ieee.mechanical_systems.all;

entity break_dot_tb is
  generic (k : real := 2.0);   -- k [1/s]
end entity break_dot_tb;

architecture behav of break_dot_tb is
  quantity x : displacement;
  quantity v : velocity tolerance velocity'tolerance;
begin
  break x'dot => 0.5;
  x'dot == k * (1.0 - x);
  v == x'dot;
end architecture behav;
