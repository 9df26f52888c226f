library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;
use work.wr_params.all;

-- worm_gear: worm gear stage of the window-regulator drive (thesis 4.1.2). One entity, three architectures
-- with the same pins (thesis 4.1.2.2), selectable per instance:
--   behavioral  4.1.2.3, Eq. 4.11/4.12: ideal gear box + friction element with a mode-dependent squeezing
--               force; parameters ratio and eta (Tab. 4.5). The drive uses it (worm_gear(behavioral)), and
--               it is the last architecture in this file, i.e. VHDL's default, as the thesis's main one.
--   three_d     4.1.2.5, Eq. 4.13-4.27: kinematics and force analysis at the contacting face in space
--               (press angle), converters at the pitch circles, Coulomb bearing friction on both shafts.
--   two_d       4.1.2.4, Eq. 4.13-4.22: the same analysis in the plane = three_d with press angle 0.
-- Ratio and efficiency of two_d/three_d are not parameters: they follow from the geometry and the friction
-- coefficients (Eq. 4.14e, 4.19e/4.26b plus the bearing losses); `ratio` and `eta` are read by behavioral
-- only, the geometry and friction generics by two_d/three_d only.
--
-- Sign convention (passive, IEEE 1076.1.1, all architectures): torque_w / torque_g = torque the model takes
-- from the worm / gear terminal; omega_w / omega_g = shaft speeds against the housing (reference,
-- rotational_v); angle_g = gear-wheel angle (an observable, the integral of omega_g from 0 at t = 0).
-- Driving mode in the positive direction: torque_w > 0, omega_g > 0, torque_g < 0.
--
-- Generics:
--   ratio, eta                   behavioral: gear ratio i = Z2/Z1 and forward power efficiency (Tab. 4.5)
--   r_worm, r_gear, lead_angle   two_d/three_d: pitch radii and lead angle (Fig. 4.26; i = r_g/(r_w tan))
--   press_angle                  three_d: press angle phi_p (two_d uses 0)
--   mu_contact                   two_d/three_d: Coulomb friction coefficient at the contacting face
--   mu_bearing, r_bearing_worm, r_bearing_gear
--                                two_d/three_d: Coulomb friction coefficient of the shaft bearings (one
--                                coefficient, as Fig. 4.26) and the friction radius of each bearing
--   omega_threshold              all: gear-wheel speed below which every friction sign is linear (4.1.2.4)
-- Defaults of the geometry are the thesis's worked examples: lead angle 6 deg with mu_contact = tan(6 deg)
-- (4.1.2.4, Eq. 4.20b: 49.4476 %), press angle 11.5 deg (4.1.2.5); the thesis gives no radii, so r_gear =
-- 29.2 mm (module 0.8 mm, 73 teeth) is assumed and r_worm = r_gear/(73 tan(6 deg)) gives i = 73; bearing
-- friction is off by default (mu_bearing = 0, as in the 4.1.2.4 example).
entity worm_gear is
  generic (
    ratio           : real             := worm_gear_ratio;            -- [1] gear ratio i = Z2/Z1 (worm revolutions per gear-wheel revolution)
    eta             : real             := worm_gear_eta;              -- [1] forward power efficiency eta = P_gear/P_worm in driving mode
    omega_threshold : angular_velocity := worm_gear_omega_threshold;  -- gear-wheel speed below which the friction sign is linear
    r_worm          : displacement     := worm_gear_r_worm;           -- pitch radius r_w of the worm
    r_gear          : displacement     := worm_gear_r_gear;           -- pitch radius r_g of the gear wheel
    lead_angle      : angle            := worm_gear_lead_angle;       -- lead angle phi_l at the pitch circle (6 deg)
    press_angle     : angle            := worm_gear_press_angle;      -- press angle phi_p (11.5 deg; three_d only)
    mu_contact      : real             := worm_gear_mu_contact;       -- [1] Coulomb friction coefficient mu_c at the contacting face
    mu_bearing      : real             := worm_gear_mu_bearing;       -- [1] Coulomb friction coefficient of the worm and gear bearings
    r_bearing_worm  : displacement     := worm_gear_r_bearing_worm;   -- friction radius of the worm-shaft bearing
    r_bearing_gear  : displacement     := worm_gear_r_bearing_gear);  -- friction radius of the gear-shaft bearing
  port (
    terminal worm, gear : rotational_v);  -- worm shaft (to the armature), gear wheel (drive output side)
end entity worm_gear;

-- three_d (thesis 4.1.2.5, Fig. 4.27; 4.1.2.4, Fig. 4.23-4.25 for the elements). Written flat: the thesis's
-- element models (two converters, the contacting face, two bearing friction models) have no state and no
-- pins of their own, so each becomes one labelled term below and the thesis's equation numbers stay on one
-- page; no translational nodes are needed for the analogy.
--   converter (Eq. 4.13, S = phi*r, M = F*r) at the worm (r_w) and at the gear (r_g): peripheral forces at
--     the pitch circles times the radii are the torques; the displacements enter the kinematics.
--   contacting face, kinetics (Eq. 4.14b; interaction on the pitch circle only, so also 3D):
--                                                omega_g*r_gear == omega_w*r_worm*tan(lead_angle)
--   contacting face, forces: normal force f_n (> 0 when the worm flank pushes the gear in the positive
--     direction) and Coulomb friction along the pitch helix, opposing the worm's sliding on the gear:
--       f_f = mu_c*|f_n|*sign(v_slide)           f_f == mu_contact*abs(f_n)*slip_sign
--     This is Eq. 4.17a (driving, F_f = -mu_c*F_n) and Eq. 4.21 (self-locking, F_f = +mu_c*F_n) in one law:
--     the mode is the sign of f_n*v_slide (driving > 0, gear-driven < 0); f_f = -F_f of Eq. 4.17a/4.24.
--     The sliding velocity has the sign of omega_g (v_slide = r_g*omega_g/sin(phi_l)), smoothed below
--     omega_threshold like every friction of the drive (4.1.2.4).
--     Worm components (Eq. 4.23a-c/4.25a-c; phi_p = 0 gives Eq. 4.15a/b and 4.18a/b):
--       f_w_tan == f_n*cos(phi_p)*sin(phi_l) + f_f*cos(phi_l)   tangential (resists the worm's rotation)
--       f_w_axi == f_n*cos(phi_p)*cos(phi_l) - f_f*sin(phi_l)   axial
--       f_w_rad == f_n*sin(phi_p)                               radial
--     Gear components by Newton's third law (Eq. 4.16a/b, 4.23g-i): tangential F_gTan = f_w_axi (drives the
--     gear), axial = f_w_tan, radial = f_w_rad. Hence F_gTan/F_wTan = Eq. 4.26a (4.19a for phi_p = 0) and,
--     with the kinematics, P_g/P_w = Eq. 4.26b (4.19e/4.20b) without bearing friction.
--   bearing friction (Coulomb, 4.1.2.4): each shaft's bearing is squeezed by the resultant of the contact
--     forces on that shaft (worm: tangential, axial, radial; gear: the same three by Newton's third law):
--       squeeze = sqrt(f_w_tan**2 + f_w_axi**2 + f_w_rad**2) = |f_n|*sqrt(1 + (mu_c*slip_sign)**2)
--     (written in the second form, which has a derivative at f_n = 0), and takes the torque
--     mu_bearing*r_bearing*squeeze*slip_sign from its shaft.
--   torque balances of the massless shafts (Eq. 4.13b + bearing):
--       torque_w == r_worm*f_w_tan + mu_bearing*r_bearing_worm*squeeze*slip_sign
--       torque_g == -r_gear*f_w_axi + mu_bearing*r_bearing_gear*squeeze*slip_sign
-- Steady driving efficiency (load-independent, all forces scale with f_n):
--   eta = (r_g*(cos_p*cos_l - mu_c*sin_l) - mu_b*r_bg*k) / (i*(r_w*(cos_p*sin_l + mu_c*cos_l) + mu_b*r_bw*k)),
--   k = sqrt(1 + mu_c**2), i = r_g/(r_w*tan_l); mu_b = 0 gives Eq. 4.26b exactly.
-- Thesis inconsistencies resolved here: Eq. 4.24 (F_f = F_n*cos(phi_p)*mu_c) with Eq. 4.25 would make the
-- efficiency independent of phi_p, contradicting Eq. 4.26; Eq. 4.26a/b follow from F_f = mu_c*F_n, which
-- is used. Eq. 4.25d (an extra cos(phi_p)) and 4.25e (sin(phi_l) where 4.25a has cos(phi_l)) contradict
-- Newton's third law with Eq. 4.25a/b (4.23g-i); the gear components are taken from the worm's. Eq.
-- 4.16e/f invert the ratio (M_w/M_g = 1/i without friction).
-- Limits: no inertia, backlash or tooth stiffness; constant friction coefficients; contact on the pitch
-- circle only. Like the behavioral architecture, a self-locked gear under a constant torque creeps at a
-- speed below omega_threshold (the smoothed friction signs are viscous there).
architecture three_d of worm_gear is
  -- worm speed [rad/s] and the torque [N*m] the model takes from the worm terminal
  quantity omega_w across torque_w through worm;
  -- gear-wheel speed omega_gear [rad/s] and the torque [N*m] the model takes from the gear terminal
  quantity omega_g across torque_g through gear;
  quantity angle_g   : angle;  -- gear-wheel angle
  quantity slip_sign : real;  -- [1] smoothed sign of the sliding velocity at the contacting face
  quantity f_n       : force;  -- normal force F_n at the contacting face (> 0: worm pushes gear forward)
  quantity f_f       : force;  -- friction force at the contacting face, opposing the worm's sliding
  quantity f_w_tan   : force;  -- tangential contact force on the worm F_wTan (= axial force on the gear)
  quantity f_w_axi   : force;  -- axial contact force on the worm F_wAxi (= tangential force on the gear F_gTan)
  quantity f_w_rad   : force;  -- radial contact force on the worm F_wRad (= radial force on the gear)
  quantity squeeze   : force;  -- resultant contact force squeezing the worm and the gear bearings
begin
  assert omega_threshold > 0.0 report "worm_gear: omega_threshold must be > 0" severity failure;
  assert r_worm > 0.0 report "worm_gear: r_worm must be > 0" severity failure;
  assert r_gear > 0.0 report "worm_gear: r_gear must be > 0" severity failure;
  assert lead_angle > 0.0 and lead_angle < 0.5 * math_pi
    report "worm_gear: lead_angle must be > 0 and < pi/2 rad" severity failure;
  assert press_angle >= 0.0 and press_angle < 0.5 * math_pi
    report "worm_gear: press_angle must be >= 0 and < pi/2 rad" severity failure;
  assert mu_contact >= 0.0 report "worm_gear: mu_contact must be >= 0" severity failure;
  assert mu_bearing >= 0.0 report "worm_gear: mu_bearing must be >= 0" severity failure;
  assert r_bearing_worm >= 0.0 report "worm_gear: r_bearing_worm must be >= 0" severity failure;
  assert r_bearing_gear >= 0.0 report "worm_gear: r_bearing_gear must be >= 0" severity failure;
  assert mu_contact * tan(lead_angle) < cos(press_angle)
    report "worm_gear: mu_contact*tan(lead_angle) must be < cos(press_angle) (else Eq. 4.26b <= 0: the worm cannot drive the gear)"
    severity failure;

  -- Eq. 4.14b: kinetics of the contacting face (converters at both pitch circles, Eq. 4.13a).
  omega_g * r_gear == omega_w * r_worm * tan(lead_angle);
  angle_g == omega_g'integ;
  slip_sign == smooth_sign(omega_g, omega_threshold);

  -- Eq. 4.17a/4.21/4.24: Coulomb friction at the contacting face (with F_f = mu_c*F_n, see header).
  f_f == mu_contact * abs(f_n) * slip_sign;

  -- Eq. 4.23a-c/4.25a-c (phi_p = 0: Eq. 4.15a/b, 4.18a/b): contact forces on the worm.
  f_w_tan == f_n * cos(press_angle) * sin(lead_angle) + f_f * cos(lead_angle);
  f_w_axi == f_n * cos(press_angle) * cos(lead_angle) - f_f * sin(lead_angle);
  f_w_rad == f_n * sin(press_angle);
  squeeze == abs(f_n) * sqrt(1.0 + (mu_contact * slip_sign)**2);

  -- Eq. 4.13b at both converters, plus the bearing friction of each shaft.
  torque_w == r_worm * f_w_tan + mu_bearing * r_bearing_worm * squeeze * slip_sign;
  torque_g == -r_gear * f_w_axi + mu_bearing * r_bearing_gear * squeeze * slip_sign;
end architecture three_d;

-- two_d (thesis 4.1.2.4, Fig. 4.23-4.25, Eq. 4.13-4.22): the force analysis in the plane. With phi_p = 0
-- every equation of three_d is the 2D one (cos = 1, sin = 0: Eq. 4.15, 4.18, 4.19, 4.20b, 4.22; the 2D
-- "radial gear force" F_gRad of Eq. 4.15c/4.18d is the 3D axial gear force), as the thesis states in
-- 4.1.2.5, so this architecture is three_d in the plane rather than a copy of it. press_angle is ignored.
-- Observables: plane.f_n, plane.f_w_tan, plane.squeeze, ... (the instance below).
architecture two_d of worm_gear is
begin
  plane: entity work.worm_gear(three_d)
    generic map (omega_threshold => omega_threshold, r_worm => r_worm, r_gear => r_gear,
                 lead_angle => lead_angle, press_angle => 0.0, mu_contact => mu_contact,
                 mu_bearing => mu_bearing, r_bearing_worm => r_bearing_worm, r_bearing_gear => r_bearing_gear)
    port map (worm => worm, gear => gear);
end architecture two_d;

-- behavioral (thesis 4.1.2.3, Fig. 4.20-4.22): an ideal gear box (ratio i) from the worm to an internal
-- node, a rotational friction element between that node and the housing, and the internal node rigidly
-- tied to the gear wheel (Eq. 4.11d). Written in this library's passive convention:
--   4.11a/d  phi_w = i*phi_g (as speeds)           omega_w == ratio * omega_g
--   4.11b    M_i = i*M_w                           m_i == ratio * torque_w
--            (m_i = torque the ideal gear box passes to the internal node; power balance
--             torque_w*omega_w = m_i*omega_g)
--   4.11c    M_g = M_i - M_f (torque balance at the internal node; -torque_g is the torque the model
--            delivers to the gear terminal, M_f = f_sq*smooth_sign(omega_g) the friction it takes)
--                                                  m_i + torque_g == f_sq * smooth_sign(omega_g, omega_threshold)
--   4.11e    M_f = F_sq (friction torque magnitude = squeezing force; the friction element supplies the
--            sign of the rotation, smoothed below omega_threshold, thesis 4.1.2.4)
--   Mode (Fig. 4.22): driving (the worm drives the gear) or gear-driven (the load drives the gear).
--   driving mode:
--     4.11f  F_sq = (1 - eta)*|M_i|
--     => -torque_g = eta*ratio*torque_w in both directions of rotation (Eq. 4.9b / 4.29b).
--   gear-driven mode:
--     F_sq = (1 - eta_back)*|M_g|
--     eta_back = max(0, 2 - 1/eta): backward efficiency from the forward one via the small-angle worm
--     relations eta = tan(lambda)/tan(lambda+phi), eta_back = tan(lambda-phi)/tan(lambda) ~ 2 - 1/eta.
--     eta <= 0.5: eta_back = 0, F_sq = |M_g| (Eq. 4.12f): self-locking, the worm receives no torque
--     (m_i = 0 once |omega_g| > omega_threshold).
--     eta > 0.5: the gear back-drives the worm, which receives eta_back*|M_g|/i (thesis 4.1.2.3, last par.).
--   The thesis decides the mode by the sign of the power at the gear (p_gear, kept as an observable). Here
--   the mode is the side that squeezes the friction element harder:
--                                                  f_sq == realmax((1-eta)*|m_i|, (1-eta_back)*|torque_g|)
--   While the gear slides (|omega_g| > omega_threshold) both rules select the same mode: driving gives
--   |torque_g| = eta*|m_i|, so (1-eta_back)*|torque_g| <= (1-eta)*|m_i| (equal for eta > 0.5); gear-driven
--   gives |m_i| = eta_back*|torque_g| and (1-eta)*eta_back <= 1-eta_back. They differ only at standstill,
--   where the power is 0 in either mode: the power rule switches equations there on a degenerate point
--   (a loaded drive coasting to a stop made ngspice fail with "timestep too small" exactly at
--   omega_g = 0 under 1.9 N*m), whereas the larger-squeeze rule is a continuous function of the torques with
--   one solution m_i for every gear speed (m_i - f_sq*smooth_sign is strictly increasing in m_i).
-- The thesis (Fig. 4.22 text) states the opposite signs for the powers because its tool reports delivered
-- power; the mode logic is the same.
-- Limits: no backlash, no tooth stiffness, no inertia (the gear wheel's inertia is negligible against the
-- armature's reflected inertia), constant efficiency (no load dependence, thesis 4.1.4.2). With the smoothed
-- sign, a self-locked gear under a constant gear torque creeps at a speed of the order of omega_threshold.
-- An overhauling load (the gear pushed in the direction the worm drives it) is gear-driven mode too: for
-- eta <= 0.5 the worm then receives no torque, whereas two_d/three_d require the worm to keep driving
-- (negative backward efficiency, Eq. 4.22b < 0).
architecture behavioral of worm_gear is
  -- Backward efficiency (gear drives worm); realmax(eta, 0.5) keeps the division defined for any eta and
  -- gives exactly 0 for eta <= 0.5.
  constant eta_back : real := realmax(0.0, 2.0 - 1.0 / realmax(eta, 0.5));  -- [1] backward efficiency
  -- worm speed [rad/s] and the torque [N*m] the model takes from the worm terminal
  quantity omega_w across torque_w through worm;
  -- gear-wheel speed omega_gear [rad/s] and the torque [N*m] the model takes from the gear terminal
  quantity omega_g across torque_g through gear;
  quantity angle_g : angle;  -- gear-wheel angle
  quantity m_i     : torque;  -- torque the ideal gear box passes to the internal node (Eq. 4.11b)
  quantity f_sq    : torque;  -- squeezing force of the friction element = friction torque magnitude (Eq. 4.11e)
  quantity p_gear  : real;  -- [W] power the model takes at the gear port (< 0: the gear delivers power)
begin
  assert ratio > 0.0 report "worm_gear: ratio must be > 0" severity failure;
  assert eta > 0.0 and eta < 1.0 report "worm_gear: eta must be > 0 and < 1" severity failure;
  assert omega_threshold > 0.0 report "worm_gear: omega_threshold must be > 0" severity failure;

  -- Eq. 4.11a/d: kinematics of the ideal gear box, internal node = gear wheel.
  omega_w == ratio * omega_g;

  -- Eq. 4.11b: torque the ideal gear box passes on.
  m_i == ratio * torque_w;

  -- Eq. 4.11c/4.12c with 4.11e: torque balance at the internal node.
  m_i + torque_g == f_sq * smooth_sign(omega_g, omega_threshold);

  -- Fig. 4.22 / Eq. 4.11f / 4.12f: working mode = the side that squeezes the friction element harder.
  f_sq == realmax((1.0 - eta) * abs(m_i), (1.0 - eta_back) * abs(torque_g));

  angle_g == omega_g'integ;
  p_gear == omega_g * torque_g;
end architecture behavioral;
