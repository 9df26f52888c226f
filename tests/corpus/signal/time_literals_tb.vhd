-- Family 13: a time literal written without a space before its unit (`2ms`: the LRM asks for one, the common
-- simulators read `2 ms`), a time divided by a real (`period / 2.0`), the position number of a time
-- (`time'pos(now)`, in fs) and the domain a process's run at initialisation sees (quiescent_domain).
-- The clock process runs at 0, 1 ms, 2 ms, ...: at initialisation s <= 0 (the quiescent domain), then
-- s <= 1 - s, and stamp <= the time of the run in seconds. So the quiescent point has s = 0 and stamp = 0, and
--   q(t) = floor(t / 1 ms) mod 2,  z(t) = floor(t / 1 ms) * 1 ms   (a signal takes its value after the run),
--   y' = (q - y)/tau, tau = 1 ms, y(0) = 0: on [k, k+1) ms, y = q_k + (y_k - q_k)*exp(-(t - k ms)/tau).
library ieee;
use ieee.math_real.all;

entity time_literals_tb is
  generic (period : time := 2ms; tau : real := 1.0e-3);   -- tau [s]
end entity time_literals_tb;

architecture behav of time_literals_tb is
  signal s : real := 0.5;
  signal stamp : real := -1.0;
  quantity q, y, z : real;
begin
  clock : process is
  begin
    if domain = quiescent_domain then
      s <= 0.0;
    else
      s <= 1.0 - s;
    end if;
    stamp <= real(time'pos(now)) * 1.0e-15;
    wait for period / 2.0;
  end process clock;

  q == s;
  z == stamp;
  break on s;
  y'dot == (q - y) / tau;
end architecture behav;
