-- Family 3: simultaneous if (piecewise-linear diode-like element) with 'above and break on.
-- vs = 5*sin(2*pi*1000*t) feeds r = 1 kOhm into node b; the element at b conducts
--   id = g_off*vd + (vd - 0.7)/r_on   when vd > 0.7,   id = g_off*vd  otherwise
-- (g_off = 1 nS, r_on = 10 Ohm; continuous at 0.7 V). Node equation (vs - vd)/r = id(vd) gives
--   vd = vs/(1 + r*g_off)                                    below 0.7 V
--   vd = (vs/r + 0.7/r_on)/(1/r + g_off + 1/r_on)            above 0.7 V
library ieee;
use ieee.electrical_systems.all;
use ieee.math_real.all;

entity clipper_tb is
  generic (amplitude : voltage := 5.0; freq : real := 1.0e3;   -- [Hz]
           r : resistance := 1.0e3; r_on : resistance := 10.0; g_off : conductance := 1.0e-9;
           knee : voltage := 0.7);
end entity clipper_tb;

architecture behav of clipper_tb is
  terminal a, b : electrical;
  quantity vs across isrc through a to electrical_ref;
  quantity vr across ir through a to b;
  quantity vd across id through b to electrical_ref;
begin
  vs == amplitude * sin(math_2_pi * freq * now);
  vr == r * ir;
  if vd'above(knee) use
    id == g_off * vd + (vd - knee) / r_on;
  else
    id == g_off * vd;
  end use;
  break on vd'above(knee);
end architecture behav;
