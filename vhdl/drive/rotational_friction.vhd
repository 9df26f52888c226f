library IEEE;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;
use work.wr_params.all;

-- rotational_friction: Coulomb friction of a shaft against the housing (reference), with the sign
-- smoothed below a velocity threshold (thesis 4.1.2.4: "linearly proportional to relative rotational
-- velocity when rotational velocity is close to zero"; break-away friction neglected). Used for the
-- worm-gear housing friction M_gc of the drive (Eq. 4.31).
--
-- Equations:
--   M_f = M_c * sign(omega)        torque == m_c * smooth_sign(omega, omega_threshold)
--
-- Sign convention (passive, IEEE 1076.1.1, rotational_v): omega = shaft speed against the housing [rad/s];
-- torque = torque the element takes from the shaft [N*m], so torque and omega have the same sign: friction
-- opposes the rotation. The element is a speed-dependent torque in every domain; at the DC operating point
-- the other elements fix the speed (the motor's omega0 through the worm gear in the drive).
--
-- Generics: m_c (friction torque magnitude), omega_threshold (smoothing band).
-- Limits: below omega_threshold the friction is a viscous damper m_c/omega_threshold, so a constant torque
-- smaller than m_c lets the shaft creep at a speed below omega_threshold instead of sticking.
entity rotational_friction is
  generic (
    m_c             : torque           := rotational_friction_m_c;               -- Coulomb friction torque magnitude
    omega_threshold : angular_velocity := rotational_friction_omega_threshold);  -- speed below which the friction torque is linear in omega
  port (
    terminal shaft : rotational_v);  -- rubbing shaft; the housing is the rotational reference
end entity rotational_friction;

architecture behavioral of rotational_friction is
  -- shaft speed [rad/s] against the housing and the friction torque [N*m] taken from the shaft
  quantity omega across torque through shaft;
begin
  assert m_c >= 0.0 report "rotational_friction: m_c must be >= 0" severity failure;
  assert omega_threshold > 0.0 report "rotational_friction: omega_threshold must be > 0" severity failure;

  torque == m_c * smooth_sign(omega, omega_threshold);
end architecture behavioral;
