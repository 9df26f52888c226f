-- Family 21 (analyses): the quiescent point and a DC sweep of a nonlinear source (wrsim run --op, --dc u ...).
-- A diode behind 100 ohm from a source u: u = v + R*Is*(exp(v/Vt) - 1), Is = 1 pA, Vt = 25 mV, R = 100 ohm:
--   v = u - Vt*W(R*Is/Vt*exp((u + R*Is)/Vt)) + R*Is   (W: Lambert's W),  i = Is*(exp(v/Vt) - 1).
-- The source is on in the quiescent domain only (where the quiescent point is solved), off in the time domain.
library ieee;
use ieee.math_real.all;

entity diode_dc_tb is
  generic (u : real := 0.7);  -- [V] source
end entity diode_dc_tb;

architecture a of diode_dc_tb is
  quantity v : real;  -- [V] diode voltage
  quantity i : real;  -- [A] diode current
  quantity s : real;  -- [V] the source
begin
  if domain = quiescent_domain use
    s == u;
  else
    s == 0.0;
  end use;
  i == 1.0e-12 * (exp(v / 0.025) - 1.0);
  s == v + 100.0 * i;
end architecture a;
