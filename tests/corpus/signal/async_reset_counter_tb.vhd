-- A counter with an asynchronous reset, in the classic flip-flop form: process (clk, rst) with
-- `elsif clk'event and clk = '1'`, and its twin with rising_edge. The reset falls at 1.7 ms while clk is '1'
-- (clk toggles every 0.5 ms from '0': rising edges at 0.5, 1.5, 2.5, 3.5 ms). That wakes the process with an
-- event on rst only, so neither counter counts then; each counts the rising edges after the reset:
--   n(t) = m(t) = #{k : t_k <= t, t_k > 1.7 ms},  t_k = 0.5 ms + (k-1)*1 ms  (1 at 2.5 ms, 2 at 3.5 ms)
library ieee;
use ieee.std_logic_1164.all;

entity async_reset_counter_tb is
  generic (half_period : time := 500 us; reset_time : time := 1.7 ms);
end entity async_reset_counter_tb;

architecture behav of async_reset_counter_tb is
  signal clk : std_ulogic := '0';
  signal rst : std_ulogic := '1';
  signal n, m : integer := 0;
  quantity qn, qm : real;
begin
  clock : process is
  begin
    wait for half_period;
    clk <= not clk;
  end process clock;

  reset : process is
  begin
    wait for reset_time;
    rst <= '0';
    wait;
  end process reset;

  by_event : process (clk, rst) is
  begin
    if rst = '1' then
      n <= 0;
    elsif clk'event and clk = '1' then
      n <= n + 1;
    end if;
  end process by_event;

  by_edge : process (clk, rst) is
  begin
    if rst = '1' then
      m <= 0;
    elsif rising_edge(clk) then
      m <= m + 1;
    end if;
  end process by_edge;

  qn == real(n);
  qm == real(m);
end architecture behav;
