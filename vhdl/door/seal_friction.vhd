library IEEE;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;
use work.wr_params.all;

-- seal_friction: friction between the glass and the door sealings along the stroke (thesis 4.3.1.1,
-- Eq. 4.43, Fig. 4.67-4.69): the normal force of a sealing grows with the contacting length, so the overall
-- sealing friction is a piecewise-linear function of the glass position (low at the bottom, higher when
-- the glass goes into the top frame), with the direction given by the glass velocity.
--
-- Equations (velocity form):
--   x   = position0 + integral of v dt   pos == position0 + v'integ
--   F_r = F(x)*sgn(v)             force == table_lookup(pos, positions, forces) * smooth_sign(v, v_threshold)
--   F(x): linear interpolation of the table, constant beyond its ends (wr_common.table_lookup).
--   sgn(v): linear between -v_threshold and +v_threshold (4.3.1.1: "a positive speed threshold ... smaller
--   than 1.0e-03 m/s ... between the thresholds, direction changes linearly"); no viscous part (glass
--   speeds 0.08 .. 0.15 m/s).
--
-- Sign convention (passive, IEEE 1076.1.1, translational_v): v = glass velocity against the door frame
-- [m/s] (positive up); pos = glass position [m] (0 = fully open); force = friction force taken from the
-- glass [N], same sign as the velocity.
--
-- Generics: positions (strictly increasing glass positions), forces (friction magnitudes >= 0 at those
-- positions; 5.3.1: about 15 N at the bottom, 40 N (Fig. 5.6) .. 65 N (Fig. 5.7) at the top),
-- v_threshold (0 < v_threshold <= 1e-3 m/s), position0 (glass position at t = 0).
-- Limits: no break-away (static) friction, no temperature dependence, no glass geometry (4.3.1.1).
entity seal_friction is
  generic (
    positions   : real_vector  := seal_friction_positions;    -- [m] glass positions of the friction table, strictly increasing
    forces      : real_vector  := seal_friction_forces;       -- [N] friction force magnitude at each position
    v_threshold : velocity     := seal_friction_v_threshold;  -- glass speed below which sgn(v) is linear in v
    position0   : displacement := seal_friction_position0);   -- glass position at t = 0
  port (
    terminal glass, frame : translational_v);  -- glass, door frame (usually the reference)
end entity seal_friction;

architecture behavioral of seal_friction is
  quantity v across force through glass to frame;  -- glass velocity [m/s], friction force [N] taken from it
  quantity pos : displacement;  -- glass position against the frame
begin
  assert positions'length = forces'length
    report "seal_friction: positions and forces must have the same length" severity failure;
  assert strictly_increasing(positions)
    report "seal_friction: positions must be strictly increasing" severity failure;
  assert all_nonnegative(forces) report "seal_friction: forces must be >= 0" severity failure;
  assert v_threshold > 0.0 and v_threshold <= 1.0e-3
    report "seal_friction: v_threshold must be in (0, 1e-3] m/s" severity failure;

  pos == position0 + v'integ;
  force == table_lookup(pos, positions, forces) * smooth_sign(v, v_threshold);   -- Eq. 4.43 with F_N(x)
end architecture behavioral;
