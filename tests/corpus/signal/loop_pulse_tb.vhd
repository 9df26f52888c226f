-- Family 16: a process written as one plain `loop ... end loop;` around its waits (a pulse source, as textbooks
-- write it), and a function with a while loop, a plain loop left by `exit when` and a for loop with `next when`
-- (all static: unrolled at elaboration).
--   p = 1 for 1 ms, then 0 for 2 ms, period 3 ms, from 1 at t = 0;
--   f = 5! = 120, r = sqrt(2) by Newton's iteration, s = 1 + 3 + 5 + 7 + 9 = 25.
entity loop_pulse_tb is
end entity loop_pulse_tb;

architecture behav of loop_pulse_tb is
  function fact(n : integer) return real is
    variable k : integer := 1;
    variable f : real := 1.0;
  begin
    loop
      exit when k > n;
      f := f * real(k);
      k := k + 1;
    end loop;
    return f;
  end function fact;

  function newton_sqrt(x : real) return real is
    variable r : real := x;
  begin
    while abs(r * r - x) > 1.0e-12 * x loop
      r := 0.5 * (r + x / r);
    end loop;
    return r;
  end function newton_sqrt;

  function odd_sum(n : integer) return real is
    variable s : real := 0.0;
  begin
    for k in 1 to n loop
      next when (k / 2) * 2 = k;
      s := s + real(k);
    end loop;
    return s;
  end function odd_sum;

  signal level : real := 0.0;
  quantity p, f, r, s : real;
begin
  source: process
  begin
    loop
      level <= 1.0;
      wait for 1 ms;
      level <= 0.0;
      wait for 2 ms;
    end loop;
  end process source;

  p == level;
  f == fact(5);
  r == newton_sqrt(2.0);
  s == odd_sum(9);
end architecture behav;
