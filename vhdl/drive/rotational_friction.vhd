library IEEE;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;

-- rotational_friction: Coulomb friction of a shaft against the housing (reference), with the sign
-- smoothed below a velocity threshold (thesis 4.1.2.4: "linearly proportional to relative rotational
-- velocity when rotational velocity is close to zero"; break-away friction neglected). Used for the
-- worm-gear housing friction M_gc of the drive (Eq. 4.31).
--
-- Equations:
--   M_f = M_c * sign(omega)        torque == m_c * smooth_sign(omega, omega_threshold)
--   omega = dphi/dt                angle'dot == omega
--
-- Sign convention (passive, IEEE 1076.1.1): angle = shaft angle against the housing [rad]; torque = torque
-- the element takes from the shaft [N*m], so torque and omega have the same sign: friction opposes the
-- rotation.
--
-- Quiescent domain (DC operating point): angle'dot is 0 there, so omega = 0 and torque = 0. The element
-- is then torque-free and deliberately places NO condition on the angle: it neither leaves an unknown of
-- its own undetermined (torque and omega are fixed) nor pins the shaft, because in the drive the gear-wheel
-- angle is already fixed by the worm-gear kinematics from the motor's angle0 and a second constraint on
-- the same node would make the DC system singular. Consequence: a shaft whose only connection is this
-- element (or that is otherwise free at DC) has an undetermined DC angle, exactly as a node with only
-- capacitors in SPICE; give it an angle from another element (an inertia/motor with angle0, a spring).
-- No static friction at DC: the DC point is computed as if the shaft could slide freely (it is at rest).
--
-- Generics: m_c (friction torque magnitude), omega_threshold (smoothing band).
-- Limits: below omega_threshold the friction is a viscous damper m_c/omega_threshold, so a constant torque
-- smaller than m_c lets the shaft creep at a speed below omega_threshold instead of sticking.
entity rotational_friction is
  generic (
    m_c             : real := 0.0;      -- [N*m] Coulomb friction torque magnitude
    omega_threshold : real := 1.0e-3);  -- [rad/s] speed below which the friction torque is linear in omega
  port (
    terminal shaft : rotational);  -- rubbing shaft; the housing is the rotational reference
end entity rotational_friction;

architecture behavioral of rotational_friction is
  -- shaft angle [rad] and the friction torque [N*m] taken from the shaft
  quantity angle across torque through shaft;
  quantity omega : real;  -- [rad/s] shaft speed against the housing
begin
  assert m_c >= 0.0 report "rotational_friction: m_c must be >= 0" severity failure;
  assert omega_threshold > 0.0 report "rotational_friction: omega_threshold must be > 0" severity failure;

  torque == m_c * smooth_sign(omega, omega_threshold);
  angle'dot == omega;
end architecture behavioral;
