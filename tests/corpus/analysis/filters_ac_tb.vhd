-- Family 21 (analyses): small-signal responses around the quiescent point (wrsim run --ac), 1076.1's frequency
-- domain, each driven by the spectrum source u = 1 V at 0 rad:
--   lag:  tau*lag'dot == u - lag                 H = 1/(1 + s*tau), tau = 1 ms
--   low:  u'ltf((1e6), (1e6, 1e3, 1))            H = 1e6/(s**2 + 1e3*s + 1e6)
--   int:  1000*u'integ                           H = 1000/s ('integ is held at 0 in the quiescent domain)
--   vc:   a series RLC network driven by u, the voltage across C:
--         H = 1/(1 + s*R*C + s**2*L*C), R = 10 ohm, L = 10 mH, C = 10 uF (f0 = 503.3 Hz, Q = 3.16)
library ieee;
use ieee.electrical_systems.all;

entity filters_ac_tb is
  generic (tau : real := 1.0e-3;                 -- [s] the lag's time constant
           r : resistance := 10.0; l : inductance := 10.0e-3; c : capacitance := 10.0e-6);
end entity filters_ac_tb;

architecture a of filters_ac_tb is
  quantity u : real spectrum 1.0, 0.0;  -- [V] source
  quantity lag : real;  -- [V] u/(1 + s*tau)
  quantity low : real;  -- [V] the 'ltf
  quantity int : real;  -- [V] 1000*u/s
  terminal p, m, n : electrical;
  quantity vs across isrc through p to electrical_ref;
  quantity vr across ir through p to m;
  quantity vl across il through m to n;
  quantity vc across ic through n to electrical_ref;
begin
  tau * lag'dot == u - lag;
  low == u'ltf((0 => 1.0e6), (1.0e6, 1.0e3, 1.0));
  int == 1000.0 * u'integ;
  vs == u;
  vr == r * ir;
  vl == l * il'dot;
  ic == c * vc'dot;
end architecture a;
