-- A delay line: q follows p 0.3 ms later with transport delay, so pulses of 0.1 ms (shorter than the delay) come
-- through, several pending at once; r, the same with the default inertial delay, swallows them all.
-- p is '1' on [0.25 k + 0.5, 0.25 k + 0.6) ms for k = 0 .. 5
--   q(t) = p(t - 0.3 ms);  r(t) = 0.
library ieee;
use ieee.std_logic_1164.all;

entity transport_delay_tb is
  generic (tpd : time := 300 us);
end entity transport_delay_tb;

architecture behav of transport_delay_tb is
  signal p, q, r : std_ulogic := '0';
  quantity qq, qr : real;
begin
  pulses : process is
  begin
    wait for 500 us;
    for k in 0 to 5 loop
      p <= '1';
      wait for 100 us;
      p <= '0';
      wait for 150 us;
    end loop;
    wait;
  end process pulses;

  line : process (p) is
  begin
    q <= transport p after tpd;
    r <= p after tpd;
  end process line;

  if q = '1' use qq == 1.0; else qq == 0.0; end use;
  if r = '1' use qr == 1.0; else qr == 0.0; end use;
end architecture behav;
