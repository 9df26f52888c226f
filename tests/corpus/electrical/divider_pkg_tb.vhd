-- Family 4: functions in a package (declaration + body), constants and subtypes.
-- u = 1 V through r1 = 3 kOhm into node b; at b the parallel pair r2 = 6 kOhm || r3 = 3 kOhm = 2 kOhm
-- (computed by the package function parallel) and c = 1 uF. Thevenin: k = 2/(3 + 2) = 0.4,
-- tau = (3 kOhm || 2 kOhm)*c = 1.2 ms:   vb(t) = 0.4*(1 - exp(-t/1.2 ms)).
library ieee;
use ieee.electrical_systems.all;

package divider_math is
  subtype ohms is real;
  constant r_top : ohms := 3.0e3;
  constant r_low_a : ohms := 6.0e3;
  constant r_low_b : ohms := 3.0e3;
  function parallel (a, b : real) return real;
  function time_constant (r, c : real) return real;
end package divider_math;

package body divider_math is
  function parallel (a, b : real) return real is
  begin
    return a * b / (a + b);
  end function parallel;

  function time_constant (r, c : real) return real is
  begin
    return r * c;
  end function time_constant;
end package body divider_math;

library ieee;
use ieee.electrical_systems.all;
use work.divider_math.all;

entity divider_pkg_tb is
  generic (u : voltage := 1.0; c : capacitance := 1.0e-6);
end entity divider_pkg_tb;

architecture behav of divider_pkg_tb is
  constant r_low : ohms := parallel(r_low_a, r_low_b);
  terminal a, b : electrical;
  quantity vs across isrc through a to electrical_ref;
  quantity vr across ir through a to b;
  quantity vb across ilow through b to electrical_ref;
  quantity vcap across icap through b to electrical_ref;
begin
  if domain = quiescent_domain use
    vs == 0.0;
  else
    vs == u;
  end use;
  vr == r_top * ir;
  vb == r_low * ilow;
  icap * time_constant(r_low, 1.0) == time_constant(r_low, c) * vcap'dot;
end architecture behav;
