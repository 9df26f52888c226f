-- Family 14: s'stable and s'stable(0 ns) of a held signal in a process: true when s has no event in the run's
-- simulation cycle (IEEE 1076 16.2), so `not s'stable` is s'event.
-- clk toggles every 1 ms (events at 1, 2, 3, 4 ms), d steps at 1.5 ms and 3.5 ms; the process on both counts
--   nc: the runs where clk changed (not clk'stable): 0, 1 at 1 ms, 2 at 2 ms, ...;
--   nd: the runs where clk did not change (clk'stable(0 ns)): the one at initialisation and those at d's changes,
--       1 from 0, 2 at 1.5 ms, 3 at 3.5 ms.
entity stable_tb is
end entity stable_tb;

architecture behav of stable_tb is
  signal clk : bit := '0';
  signal d, nc, nd : integer := 0;
  quantity qc, qd : real;
begin
  clk <= not clk after 1 ms;

  stimulus : process is
  begin
    wait for 1.5 ms;
    d <= 1;
    wait for 2 ms;
    d <= 2;
    wait;
  end process stimulus;

  count : process (clk, d) is
  begin
    if not clk'stable then
      nc <= nc + 1;
    end if;
    if clk'stable(0 ns) then
      nd <= nd + 1;
    end if;
  end process count;

  qc == real(nc);
  qd == real(nd);
end architecture behav;
