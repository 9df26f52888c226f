library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;

-- worm_gear: worm gear stage of the window-regulator drive (thesis 4.1.2). The entity is shared by all
-- architectures (thesis 4.1.2.2: behavioral, 2D, 3D share the pins); this file holds the behavioral
-- architecture (4.1.2.3, Fig. 4.20-4.22). Later architectures (two_d, three_d) add their own generics
-- to this entity, with defaults, and keep the ports.
--
-- Behavioral architecture: an ideal gear box (ratio i) from the worm to an internal node, a rotational
-- friction element between that node and the housing, and the internal node rigidly tied to the gear
-- wheel (Eq. 4.11d). Written in this library's passive convention:
--   4.11a/d  phi_w = i*phi_g                       angle_w == ratio * angle_g
--   4.11b    M_i = i*M_w                           m_i == ratio * torque_w
--            (m_i = torque the ideal gear box passes to the internal node; power balance
--             torque_w*omega_w = m_i*omega_g)
--   4.11c    M_g = M_i - M_f (torque balance at the internal node; -torque_g is the torque the model
--            delivers to the gear terminal, M_f = f_sq*smooth_sign(omega_g) the friction it takes)
--                                                  m_i + torque_g == f_sq * smooth_sign(omega_g, omega_threshold)
--   4.11e    M_f = F_sq (friction torque magnitude = squeezing force; the friction element supplies the
--            sign of the rotation, smoothed below omega_threshold, thesis 4.1.2.4)
--   Mode (Fig. 4.22), decided by the power the model takes at the gear, p_gear = omega_g*torque_g:
--   driving mode, p_gear <= 0 (the gear delivers power, the worm drives):
--     4.11f  F_sq = (1 - eta)*|M_i|                f_sq == (1.0 - eta) * abs(m_i)
--     => -torque_g = eta*ratio*torque_w in both directions of rotation (Eq. 4.9b / 4.29b).
--   gear-driven mode, p_gear > 0 (the load drives the gear):
--     F_sq = (1 - eta_back)*|M_g|                  f_sq == (1.0 - eta_back) * abs(torque_g)
--     eta_back = max(0, 2 - 1/eta): backward efficiency from the forward one via the small-angle worm
--     relations eta = tan(lambda)/tan(lambda+phi), eta_back = tan(lambda-phi)/tan(lambda) ~ 2 - 1/eta.
--     eta <= 0.5: eta_back = 0, F_sq = |M_g| (Eq. 4.12f): self-locking, the worm receives no torque
--     (m_i = 0 once |omega_g| > omega_threshold).
--     eta > 0.5: the gear back-drives the worm, which receives eta_back*|M_g|/i (thesis 4.1.2.3, last par.).
--   Both modes give the same torques at p_gear = 0, so the switch is continuous in value.
--
-- Sign convention (passive, IEEE 1076.1.1): torque_w / torque_g = torque the model takes from the worm /
-- gear terminal; angle_w / angle_g against the housing (reference). Driving mode in the positive
-- direction: torque_w > 0, omega_g > 0, torque_g < 0, p_gear < 0. The thesis (Fig. 4.22 text) states the
-- opposite signs for the powers because its tool reports delivered power; the mode logic is the same.
--
-- Generics: ratio (i of Tab. 4.5), eta (forward power efficiency of Tab. 4.5), omega_threshold (smoothing
-- of the friction sign on the gear-wheel side; at the armature it is ratio times larger).
-- Limits: no backlash, no tooth stiffness, no inertia (the gear wheel's inertia is negligible against the
-- armature's reflected inertia), constant efficiency (no load dependence, thesis 4.1.4.2). With the smoothed
-- sign, a self-locked gear under a constant gear torque creeps at a speed of the order of omega_threshold.
entity worm_gear is
  generic (
    ratio           : real := 73.0;     -- [1] gear ratio i = Z2/Z1 (worm revolutions per gear-wheel revolution)
    eta             : real := 0.45;     -- [1] forward power efficiency eta = P_gear/P_worm in driving mode
    omega_threshold : real := 1.0e-3);  -- [rad/s] gear-wheel speed below which the friction sign is linear
  port (
    terminal worm, gear : rotational);  -- worm shaft (to the armature), gear wheel (drive output side)
end entity worm_gear;

architecture behavioral of worm_gear is
  -- Backward efficiency (gear drives worm); realmax(eta, 0.5) keeps the division defined for any eta and
  -- gives exactly 0 for eta <= 0.5.
  constant eta_back : real := realmax(0.0, 2.0 - 1.0 / realmax(eta, 0.5));  -- [1] backward efficiency
  -- worm angle [rad] and the torque [N*m] the model takes from the worm terminal
  quantity angle_w across torque_w through worm;
  -- gear-wheel angle [rad] and the torque [N*m] the model takes from the gear terminal
  quantity angle_g across torque_g through gear;
  quantity omega_g : real;  -- [rad/s] gear-wheel speed omega_gear
  quantity m_i     : real;  -- [N*m] torque the ideal gear box passes to the internal node (Eq. 4.11b)
  quantity f_sq    : real;  -- [N*m] squeezing force of the friction element = friction torque magnitude (Eq. 4.11e)
  quantity p_gear  : real;  -- [W] power the model takes at the gear port (< 0: the gear delivers power)
begin
  assert ratio > 0.0 report "worm_gear: ratio must be > 0" severity failure;
  assert eta > 0.0 and eta < 1.0 report "worm_gear: eta must be > 0 and < 1" severity failure;
  assert omega_threshold > 0.0 report "worm_gear: omega_threshold must be > 0" severity failure;

  -- Eq. 4.11a/d: kinematics of the ideal gear box, internal node = gear wheel.
  angle_w == ratio * angle_g;

  -- Eq. 4.11b: torque the ideal gear box passes on.
  m_i == ratio * torque_w;

  -- Eq. 4.11c/4.12c with 4.11e: torque balance at the internal node.
  m_i + torque_g == f_sq * smooth_sign(omega_g, omega_threshold);

  -- Fig. 4.22: working mode from the power at the gear.
  if p_gear'above(0.0) use
    -- gear-driven (self-locking for eta <= 0.5, Eq. 4.12f; back-driving for eta > 0.5)
    f_sq == (1.0 - eta_back) * abs(torque_g);
  else
    -- driving mode, Eq. 4.11f
    f_sq == (1.0 - eta) * abs(m_i);
  end use;
  break on p_gear'above(0.0);

  omega_g == angle_g'dot;
  p_gear == omega_g * torque_g;
end architecture behavioral;
