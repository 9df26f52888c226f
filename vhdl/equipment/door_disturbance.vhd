library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;
use work.wr_params.all;

-- door_disturbance: what the door does to the glass on a closing without an obstacle, for counting the false
-- reversals of an anti-pinch algorithm (docs/anti-pinch.md, "Disturbances"). From t_on on:
--   rough road  the door moves vertically with the acceleration a(t) = accel*sin(2*pi*frequency*(t - t_on)).
--               Seen from the door (the frame the glass position is measured in) the glass feels the inertial
--               force -glass_mass*a(t): the base excitation of a mass on a spring, the two-mass system of
--               thesis 3.1 with the door as the excited mass and the glass on its cable springs as the other;
--   seals       the seals grip more (cold rubber) or less (wet or worn seals) than when the ECU learned its
--               reference: an extra Coulomb friction `friction` against the glass velocity (< 0: less friction;
--               keep |friction| below the seal friction of the door, 15 N at the bottom in rail_wr_8p5nm).
-- Before t_on the element takes no force, so the normalization learns the undisturbed door.
--
-- Equations (t >= t_on):
--   force == glass_mass*accel*sin(2*pi*frequency*(now - t_on)) + friction*smooth_sign(v, v_threshold)
--
-- Sign convention (passive, IEEE 1076.1.1, translational_v): v = glass velocity against the door frame [m/s]
-- (positive up); force = force the element takes from the glass [N] (> 0: it pushes the glass down).
--
-- Generics: glass_mass (the door's glass, 2.55 kg in rail_wr_8p5nm), accel [m/s**2], frequency [Hz],
-- friction [N], t_on [s], v_threshold [m/s] (as seal_friction).
-- Limits: a rigid door (its own modes are not modelled), one sinusoid (no road spectrum), the friction change
-- the same along the whole stroke. Switched on at t_on with the glass at rest: both terms start from 0.
entity door_disturbance is
  generic (
    glass_mass  : mass         := door_disturbance_glass_mass;    -- mass of the glass the door carries
    accel       : acceleration := door_disturbance_accel;         -- amplitude of the door's vertical acceleration
    frequency   : real         := door_disturbance_frequency;     -- [Hz] frequency of that acceleration
    friction    : force        := door_disturbance_friction;      -- extra seal friction against the glass velocity (< 0: less)
    t_on        : real         := door_disturbance_t_on;          -- [s] the disturbance starts
    v_threshold : velocity     := door_disturbance_v_threshold);  -- speed below which sgn(v) is linear
  port (
    terminal glass, frame : translational_v);  -- glass edge, door frame
end entity door_disturbance;

architecture behavioral of door_disturbance is
  quantity v across force through glass to frame;  -- glass velocity [m/s], force [N] taken from the glass
begin
  assert glass_mass > 0.0 report "door_disturbance: glass_mass must be > 0" severity failure;
  assert frequency > 0.0 report "door_disturbance: frequency must be > 0" severity failure;
  assert v_threshold > 0.0 and v_threshold <= 1.0e-3
    report "door_disturbance: v_threshold must be in (0, 1e-3] m/s" severity failure;
  if now >= t_on use
    force == glass_mass * accel * sin(math_2_pi * frequency * (now - t_on)) + friction * smooth_sign(v, v_threshold);
  else
    force == 0.0;
  end use;
end architecture behavioral;
