-- Family 15b: a break list at t = 0 that sets a quantity and its derivative, with the model written in the second
-- derivative (`break x => 1.0, x'dot => -w;` and `x'dot'dot == -w**2 * x`), the harmonic oscillator:
--   x(t) = cos(w*t) - sin(w*t),  v = x'dot = -w*(sin(w*t) + cos(w*t)),  w = 2 rad/s.
-- The compiled device once gave x'dot(0) = -w/2 here (the break's value and the derivative's own row both on one
-- row at the quiescent point), with no error.
entity break_dotdot_tb is
  generic (w : real := 2.0);   -- [rad/s]
end entity break_dotdot_tb;

architecture behav of break_dotdot_tb is
  quantity x, v : real;
begin
  break x => 1.0, x'dot => -w;
  x'dot'dot == -w * w * x;
  v == x'dot;
end architecture behav;
