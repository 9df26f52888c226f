-- Family 9: a process sensitive to x'above(th) drives a real signal that a simultaneous statement reads.
-- RC 1 (tau1 = 10 ms) charges v1 = 1 - exp(-t/tau1); at t1 = tau1*ln(2) = 6.931 ms v1 rises above 0.5 and the
-- process sets s to 1.0; source 2 = 2*s charges RC 2 (tau2 = 5 ms):
--   v2(t) = 0 for t < t1,  v2(t) = 2*(1 - exp(-(t - t1)/tau2)) for t >= t1
library ieee;
use ieee.electrical_systems.all;

entity process_threshold_tb is
  generic (threshold : voltage := 0.5);
end entity process_threshold_tb;

architecture behav of process_threshold_tb is
  signal s : real := 0.0;
  terminal a, b, d, e : electrical;
  quantity vs1 across is1 through a to electrical_ref;
  quantity vr1 across ir1 through a to b;
  quantity v1 across ic1 through b to electrical_ref;
  quantity vs2 across is2 through d to electrical_ref;
  quantity vr2 across ir2 through d to e;
  quantity v2 across ic2 through e to electrical_ref;
begin
  detector : process is
  begin
    wait on v1'above(threshold);
    if v1'above(threshold) then
      s <= 1.0;
    else
      s <= 0.0;
    end if;
  end process detector;

  if domain = quiescent_domain use
    vs1 == 0.0;
  else
    vs1 == 1.0;
  end use;
  vr1 == 10.0e3 * ir1;
  ic1 == 1.0e-6 * v1'dot;

  vs2 == 2.0 * s;
  break on s;
  vr2 == 5.0e3 * ir2;
  ic2 == 1.0e-6 * v2'dot;
end architecture behav;
