-- Family 21 (analyses): the output noise of an inverting op-amp integrator (wrsim run --noise vo ...), and its
-- small-signal gain. R = 10 kohm (its thermal noise 4*k*T*R, T = 300 K, in series), C = 100 nF, an op-amp of
-- gain A = 1e6 (vo = A*(en - v(inv)), en its input voltage noise, 10 nV/sqrt(Hz)). With Y = j*w*R*C, w = 2*pi*f
-- and G = 1/(Y + (1 + Y)/A):
--   vo noise = sqrt(|(1 + Y)*G|**2 * en**2 + |G|**2 * 4*k*T*R)      [V/sqrt(Hz)]
--   vo / u   = -G                                                  (-1/Y for A -> infinity: an integrator)
library ieee;
use ieee.electrical_systems.all;

entity integrator_noise_tb is
  generic (r : resistance := 10.0e3; c : capacitance := 100.0e-9;
           a_gain : real := 1.0e6;  -- [1] the op-amp's open-loop gain
           en : real := 10.0e-9);   -- [V] the op-amp's input voltage noise density per sqrt(Hz)
end entity integrator_noise_tb;

architecture a of integrator_noise_tb is
  constant k_boltzmann : real := 1.380649e-23;
  terminal inp, inv, outp : electrical;
  quantity u : real spectrum 1.0, 0.0;                         -- [V] the input's small-signal source
  quantity vn_r : real noise 4.0 * k_boltzmann * 300.0 * r;    -- [V] the resistor's thermal noise
  quantity vn_op : real noise en * en;                         -- [V] the op-amp's input voltage noise
  quantity vin across iin through inp to electrical_ref;
  quantity vr across ir through inp to inv;
  quantity vcap across icap through inv to outp;
  quantity vd across inv to electrical_ref;
  quantity vo across io through outp to electrical_ref;
begin
  vin == u;
  vr == r * ir + vn_r;
  icap == c * vcap'dot;
  vo == a_gain * (vn_op - vd);
end architecture a;
