-- A stimulus process with waits of several kinds in sequence (a state machine): it steps the source of an RC lag
-- (tau = 1 ms) to 1 V, waits until the output passes 0.5 V, waits 2 ms more, steps the source to 0 and waits
-- until the output falls below 0.25 V, then stops. phase counts the waits passed:
--   t1 = tau*ln 2 = 0.6931 ms (phase 1), t2 = t1 + 2 ms (phase 2, source 0),
--   v(t2) = 1 - exp(-t2/tau), t3 = t2 + tau*ln(v(t2)/0.25) (phase 3);
--   v = 1 - exp(-t/tau) up to t2, v(t2)*exp(-(t - t2)/tau) after.
library ieee;

entity wait_sequence_tb is
  generic (tau : real := 1.0e-3; hold_time : time := 2 ms);   -- tau [s]
end entity wait_sequence_tb;

architecture behav of wait_sequence_tb is
  signal vs : real := 0.0;
  signal phase : integer := 0;
  quantity v, ph : real;
begin
  stimulus : process is
  begin
    vs <= 1.0;
    wait until v'above(0.5);
    phase <= 1;
    wait for hold_time;
    phase <= 2;
    vs <= 0.0;
    wait until not v'above(0.25);
    phase <= 3;
    wait;
  end process stimulus;

  break v => 0.0;                  -- the lag starts empty (else the quiescent point puts v at vs)
  v'dot == (vs - v) / tau;
  ph == real(phase);
end architecture behav;
