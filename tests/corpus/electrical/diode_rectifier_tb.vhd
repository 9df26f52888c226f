-- Family 3/4: exponential (Shockley) diode half-wave rectifier with a smoothing RC, math_real exp.
-- vs = 5*sin(2*pi*1 kHz*t); diode a -> b with id = is_d*(exp(vd/(n*vt)) - 1), is_d = 1e-14 A, n*vt = 25.85 mV;
-- at b: r_load = 1 kOhm || c = 10 uF:   c*vb' = id(vs - vb) - vb/r_load.  Reference: SciPy solve_ivp (Radau).
library ieee;
use ieee.electrical_systems.all;
use ieee.math_real.all;

entity diode_rectifier_tb is
  generic (amplitude : voltage := 5.0; freq : real := 1.0e3;   -- [Hz]
           is_d : current := 1.0e-14; nvt : voltage := 0.02585;
           r_load : resistance := 1.0e3; c : capacitance := 10.0e-6);
end entity diode_rectifier_tb;

architecture behav of diode_rectifier_tb is
  terminal a, b : electrical;
  quantity vs across isrc through a to electrical_ref;
  quantity vd across id through a to b;
  quantity vb across il through b to electrical_ref;
  quantity vcap across icap through b to electrical_ref;
begin
  vs == amplitude * sin(math_2_pi * freq * now);
  id == is_d * (exp(vd / nvt) - 1.0);
  vb == r_load * il;
  icap == c * vcap'dot;
end architecture behav;
