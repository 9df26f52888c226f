-- Family 3: 'above in a simultaneous if (a comparator switching a source) with break on.
-- RC 1 (10 kOhm, 1 uF, tau1 = 10 ms) charges to 1 V: v1 = 1 - exp(-t/tau1). When v1 rises above 0.5 V,
-- at t1 = tau1*ln(2) = 6.931 ms, the comparator switches source 2 from 0 V to 2 V, which charges
-- RC 2 (tau2 = 5 ms):  v2(t) = 0 for t < t1,  v2(t) = 2*(1 - exp(-(t - t1)/tau2)) for t >= t1.
library ieee;
use ieee.electrical_systems.all;

entity comparator_tb is
  generic (r1 : resistance := 10.0e3; c1 : capacitance := 1.0e-6;
           r2 : resistance := 5.0e3; c2 : capacitance := 1.0e-6; threshold : voltage := 0.5);
end entity comparator_tb;

architecture behav of comparator_tb is
  terminal a, b, d, e : electrical;
  quantity vs1 across is1 through a to electrical_ref;
  quantity vr1 across ir1 through a to b;
  quantity v1 across ic1 through b to electrical_ref;
  quantity vs2 across is2 through d to electrical_ref;
  quantity vr2 across ir2 through d to e;
  quantity v2 across ic2 through e to electrical_ref;
begin
  if domain = quiescent_domain use
    vs1 == 0.0;
  else
    vs1 == 1.0;
  end use;
  vr1 == r1 * ir1;
  ic1 == c1 * v1'dot;

  if v1'above(threshold) use
    vs2 == 2.0;
  else
    vs2 == 0.0;
  end use;
  break on v1'above(threshold);
  vr2 == r2 * ir2;
  ic2 == c2 * v2'dot;
end architecture behav;
