-- Family 14: signals that change at the same instant (IEEE 1076 14.7.5: a process sensitive to several signals
-- runs once per simulation cycle in which any of them changes, with 'event true for each one that did).
-- a toggles every 1 ms from '0' (1, 2, 3, 4, 5, 6 ms), b every 1.5 ms from '0' (1.5, 3, 4.5, 6 ms): both change
-- at 3 ms (a rises, b falls) and at 6 ms (both fall); d <= a follows a one delta cycle later (a run for each);
--   n: +10 where a and b change together, +1 where one does: 1, 2, 3, 13, 14, 15, 16, 26 at
--      1, 1.5, 2, 3, 4, 4.5, 5, 6 ms;
--   c: one run at initialisation and one per instant: 1, then + 1 at each of the eight instants (9 from 6 ms);
--   s: the runs in which a'stable (at initialisation and where b changes alone): 1, 2 at 1.5 ms, 3 at 4.5 ms;
--   e: rising_edge(a) and falling_edge(b) together: 1 at 3 ms;
--   x: process (a, d) counts like n, two single changes a delta cycle apart: + 2 at each change of a.
entity simultaneous_events_tb is
end entity simultaneous_events_tb;

architecture behav of simultaneous_events_tb is
  signal a, b, d : bit := '0';
  signal n, c, s, e, x : integer := 0;
  quantity qn, qc, qs, qe, qx : real;
begin
  toggle_a : process is
  begin
    wait for 1 ms;
    a <= not a;
  end process toggle_a;

  toggle_b : process is
  begin
    wait for 1.5 ms;
    b <= not b;
  end process toggle_b;

  d <= a;

  together : process (a, b) is
  begin
    if a'event and b'event then
      n <= n + 10;
    elsif a'event or b'event then
      n <= n + 1;
    end if;
  end process together;

  runs : process (a, b) is
  begin
    c <= c + 1;
  end process runs;

  stable : process (a, b) is
  begin
    if a'stable then
      s <= s + 1;
    end if;
  end process stable;

  edges : process (b, a) is
  begin
    if rising_edge(a) and falling_edge(b) then
      e <= e + 1;
    end if;
  end process edges;

  deltas : process (a, d) is
  begin
    if a'event and d'event then
      x <= x + 10;
    elsif a'event or d'event then
      x <= x + 1;
    end if;
  end process deltas;

  qn == real(n);
  qc == real(c);
  qs == real(s);
  qe == real(e);
  qx == real(x);
end architecture behav;
