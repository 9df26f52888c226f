-- Family 16: frequency-domain source quantities (spectrum, noise) contribute nothing in the time domain.
-- The RC charge of rc_charge_tb with a spectrum source and a noise source added to the step:
--   vc(t) = 1 - exp(-t/1 ms)
library ieee;
use ieee.electrical_systems.all;

entity noise_rc_tb is
  generic (r : resistance := 1.0e3; c : capacitance := 1.0e-6);
end entity noise_rc_tb;

architecture behav of noise_rc_tb is
  constant k_boltzmann : real := 1.380649e-23;
  terminal a, b : electrical;
  quantity vs across isrc through a to electrical_ref;
  quantity vr across ir through a to b;
  quantity vc across ic through b to electrical_ref;
  quantity v_ac : real spectrum 1.0, 0.0;                        -- AC stimulus: 1 V, 0 rad
  quantity v_noise : real noise 4.0 * k_boltzmann * 300.0 * r;   -- thermal noise of r [V**2/Hz]
begin
  if domain = quiescent_domain use
    vs == 0.0;
  else
    vs == 1.0 + v_ac;
  end use;
  vr == r * ir + v_noise;
  ic == c * vc'dot;
end architecture behav;
