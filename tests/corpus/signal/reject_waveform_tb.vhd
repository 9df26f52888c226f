-- Family 14: the delay mechanisms of IEEE 1076 10.5.2.2 on one stimulus: x = 1 on [1, 1.5) ms and [1.7, 2) ms.
-- u <= x after 1 ms (inertial, limit 1 ms): both pulses are shorter than the delay, u stays 0;
-- y <= reject 0.4 ms inertial x after 1 ms: the 0.5 ms pulse passes, the 0.2 ms gap and the 0.3 ms pulse
--   after it do not: y = 1 on [2, 3) ms;
-- z <= transport x after 1 ms, 5.0 after 1.5 ms (a waveform of two elements; the run at initialisation too):
--   z = 5 on [1.5, 2), 1 on [2, 2.5), 0 on [2.5, 2.7), 1 on [2.7, 3), 0 on [3, 3.5) ms, 5 from 3.5 ms;
-- w <= x after 0.1 ms, 2.0 * x after 0.2 ms (inertial first element, the second added after it):
--   w = 1 on [1.1, 1.2), 2 on [1.2, 1.6), 0 on [1.6, 1.8), 1 on [1.8, 1.9), 2 on [1.9, 2.1) ms, 0 elsewhere;
-- q <= 1.0 after 1.5 ms at every change of clk (every 0.5 ms): an inertial assignment of the value already
--   pending keeps its arrival, q = 1 from 1.5 ms (the run at initialisation's).
entity reject_waveform_tb is
end entity reject_waveform_tb;

architecture behav of reject_waveform_tb is
  signal clk : bit := '0';
  signal x, u, y, z, w, q : real := 0.0;
  quantity qu, qy, qz, qw, qq : real;
begin
  clk <= not clk after 0.5 ms;

  stimulus : process is
  begin
    wait for 1 ms;
    x <= 1.0;
    wait for 0.5 ms;
    x <= 0.0;
    wait for 0.2 ms;
    x <= 1.0;
    wait for 0.3 ms;
    x <= 0.0;
    wait;
  end process stimulus;

  delays : process (x) is
  begin
    u <= x after 1 ms;
    y <= reject 0.4 ms inertial x after 1 ms;
    z <= transport x after 1 ms, 5.0 after 1.5 ms;
  end process delays;

  w <= x after 0.1 ms, 2.0 * x after 0.2 ms;

  again : process (clk) is
  begin
    q <= 1.0 after 1.5 ms;
  end process again;

  qu == u;
  qy == y;
  qz == z;
  qw == w;
  qq == q;
end architecture behav;
