-- Signal assignments `after` a delay (inertial, the VHDL default), from a stimulus and from an 'above event.
-- p is '1' on [1.0, 1.1) ms and [2.0, 2.5) ms; q <= p after 0.2 ms: the 0.1 ms pulse is shorter than the delay,
-- so it is swallowed (its end replaces the pending '1'); the 0.5 ms pulse comes through, 0.2 ms late:
--   q = '1' on [2.2, 2.7) ms, '0' elsewhere.
-- x = sin(2*pi*500*t) crosses 0.5 upwards at t_up = (1/12 + k)/500 s and downwards at (5/12 + k)/500 s;
-- level <= 2.0 / -1.0 after 0.1 ms on x'above(0.5): level = 2.0 on [t_up + 0.1 ms, t_down + 0.1 ms).
library ieee;
use ieee.std_logic_1164.all;
use ieee.math_real.all;

entity inertial_delay_tb is
  generic (tpd : time := 200 us);
end entity inertial_delay_tb;

architecture behav of inertial_delay_tb is
  signal p, q : std_ulogic := '0';
  signal level : real := -1.0;
  quantity x, qq, lv : real;
begin
  stimulus : process is
  begin
    wait for 1 ms;
    p <= '1';
    wait for 100 us;
    p <= '0';
    wait for 900 us;
    p <= '1';
    wait for 500 us;
    p <= '0';
    wait;
  end process stimulus;

  follow : process (p) is
  begin
    q <= p after tpd;
  end process follow;

  watch : process (x'above(0.5)) is
  begin
    if x'above(0.5) then
      level <= 2.0 after 100 us;
    else
      level <= -1.0 after 100 us;
    end if;
  end process watch;

  x == sin(math_2_pi * 500.0 * now);
  if q = '1' use qq == 1.0; else qq == 0.0; end use;
  lv == level;
end architecture behav;
