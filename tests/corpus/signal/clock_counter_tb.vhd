-- Families 9 and 10: a std_ulogic clock process (wait for a time generic), an integer counter signal and a
-- staircase quantity filtered by a first-order lag.
-- clk toggles every half_period = 0.5 ms starting at '0', so rising edges at t_k = 0.5 ms + (k-1)*1 ms; count
-- increments on each. q = 0.5*count; y' = (q - y)/tau with tau = 1 ms, y(0) = 0:
--   q(t) = 0.5*#{k : t_k <= t},  y(t) = sum over t_k <= t of 0.5*(1 - exp(-(t - t_k)/tau))
library ieee;
use ieee.std_logic_1164.all;
use ieee.math_real.all;

entity clock_counter_tb is
  generic (half_period : time := 500 us; tau : real := 1.0e-3);   -- tau [s]
end entity clock_counter_tb;

architecture behav of clock_counter_tb is
  signal clk : std_ulogic := '0';
  signal count : integer := 0;
  quantity q, y : real;
begin
  clock : process is
  begin
    wait for half_period;
    clk <= not clk;
  end process clock;

  counter : process (clk) is
  begin
    if rising_edge(clk) then
      count <= count + 1;
    end if;
  end process counter;

  q == 0.5 * real(count);
  break on count;
  y'dot == (q - y) / tau;
end architecture behav;
