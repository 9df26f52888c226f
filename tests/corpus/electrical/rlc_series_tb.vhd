-- Family 1: series RLC, underdamped step response.
-- r = 20 Ohm, l = 10 mH, c = 1 uF: w0 = 1/sqrt(l*c) = 1e4 rad/s, alpha = r/(2*l) = 1000 1/s,
-- wd = sqrt(w0**2 - alpha**2). For a step u:
--   vc(t) = u*(1 - exp(-alpha*t)*(cos(wd*t) + alpha/wd*sin(wd*t)))
--   i(t)  = u*c*(w0**2/wd)*exp(-alpha*t)*sin(wd*t)
library ieee;
use ieee.electrical_systems.all;

entity rlc_series_tb is
  generic (u : voltage := 1.0; r : resistance := 20.0; l : inductance := 10.0e-3; c : capacitance := 1.0e-6);
end entity rlc_series_tb;

architecture behav of rlc_series_tb is
  terminal a, b, d : electrical;
  quantity vs across isrc through a to electrical_ref;
  quantity vr across ir through a to b;
  quantity vl across il through b to d;
  quantity vc across ic through d to electrical_ref;
begin
  if domain = quiescent_domain use
    vs == 0.0;
  else
    vs == u;
  end use;
  vr == r * ir;
  vl == l * il'dot;
  ic == c * vc'dot;
end architecture behav;
