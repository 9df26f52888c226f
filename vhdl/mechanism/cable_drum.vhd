library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;
use work.wr_params.all;

-- cable_drum: cable drum of the rail window-regulator mechanism (thesis 4.2.1.1, Fig. 4.46/4.47, Eq. 4.36,
-- Tab. 4.9): two windlasses of the same radius on the drive's output shaft, one per cable end, plus the
-- sliding friction between drive gear and gear shaft, pressed by the resultant of the two cable forces.
--
-- Equations (Eq. 4.36, written in this library's passive convention, see below):
--   4.36a  S_cd = phi_cd*r_cd = S_c1 = S_c2      (velocity form) v_a == r_cd*omega; v_b == r_cd*omega
--   4.36c  M_c  = r_cd*(F_c1 - F_c2)             with F_c1 = -force_a, F_c2 = force_b
--   4.36e  F_cn = sqrt(F_c1**2 + F_c2**2 - 2*cos(alpha_c)*F_c1*F_c2), F_c1, F_c2 clipped at >= 0
--   4.36d  M_cf = mu_gs*F_cn*r_gs, opposing the rotation: smooth_sign(omega, omega_threshold) (4.1.2.4)
--   4.36b  M_cd = M_c + M_cf                     torque == m_c + m_cf + j_cd*alpha (drum inertia, below)
--   4.36f  eta_cd = M_c/M_cd                     (not a quantity; the benches compute it from m_c and torque)
-- alpha_c is used exactly as printed in Eq. 4.36e: alpha_c = 180 deg gives F_cn = F_c1 + F_c2 (both cables
-- pull the drum to the same side), alpha_c = 0 gives |F_c1 - F_c2|. The thesis calls it the "angle between
-- two cables"; as a geometric angle between the two pull directions it is 180 deg minus this value (the
-- same convention as the wrap angle of the pulley, Eq. 4.39c).
-- The cable terminals are of nature translational_v (across = cable velocity): the mechanism models are
-- written in velocity form, positions are integrals of velocities (see rail_wr), which keeps the friction
-- laws well conditioned at standstill. j_cd is the inertia of drum and drive output: the thesis neglects
-- it (Tab. 4.8: its kinetic energy is negligible); a small physical value is kept so that the drum node,
-- which carries the Coulomb friction of Eq. 4.36d between the rubber damper and the cable springs, has a
-- state (a massless node with Coulomb friction between two springs has no unique velocity).
--
-- Sign convention (passive, IEEE 1076.1.1; cable loop as in the mechanism models of vhdl/mechanism):
--   omega = drum (= drive output) speed against the housing [rad/s] (rotational_v), positive = lifting the
--   glass; angle = its integral from 0 at t = 0 [rad] (an observable); torque =
--   torque the drum takes from the drive shaft [N*m] (> 0 while the drive lifts against the load).
--   Cable velocities v_a, v_b [m/s] are positive in the direction the cable moves while the glass is
--   lifted. cable_a is the port the cable is wound onto while lifting (upper cable, cable 1),
--   cable_b the port it is paid out from (lower cable, cable 2). Every element of the loop takes its
--   a-side tension from its cable_a terminal, so at the drum (which closes the loop) the through forces are
--   force_a = -F_c1 (the drum delivers the pull of cable 1 to the loop) and force_b = +F_c2.
--   Power check: torque*omega + (force_a + force_b)*r_cd*omega = M_cf*|omega| + d/dt(J*omega**2/2).
--
-- Generics: r_cd (wrapping radius), r_gs (gear-shaft radius), alpha_c (Eq. 4.36e angle), mu_gs (friction
-- coefficient gear/shaft; the thesis guides 0.06 .. 0.20), j_cd, omega_threshold.
-- Limits: rigid cable, no slack, one winding radius, no cable stiffness (4.2.1).
entity cable_drum is
  generic (
    r_cd            : displacement     := cable_drum_r_cd;              -- wrapping radius of the cable r_cd (Tab. 4.9)
    r_gs            : displacement     := cable_drum_r_gs;              -- radius of the gear shaft r_gs (Tab. 4.9)
    alpha_c         : angle            := cable_drum_alpha_c;           -- angle alpha_c of Eq. 4.36e (Tab. 4.9, see header)
    mu_gs           : real             := cable_drum_mu_gs;             -- [1] Coulomb friction coefficient gear/shaft mu_gs (Tab. 4.9)
    j_cd            : moment_inertia   := cable_drum_j_cd;              -- inertia of drum and drive output (see header)
    omega_threshold : angular_velocity := cable_drum_omega_threshold);  -- speed below which the friction torque is linear in omega
  port (
    terminal shaft            : rotational_v;    -- drive output shaft
    terminal cable_a, cable_b : translational_v);  -- upper cable (wound on while lifting), lower cable
end entity cable_drum;

architecture behavioral of cable_drum is
  -- drum speed [rad/s] and the torque M_cd [N*m] the drum takes from the drive shaft
  quantity omega across torque through shaft;
  -- cable velocities [m/s] and the forces [N] the drum takes from the two cable terminals
  quantity v_a across force_a through cable_a;
  quantity v_b across force_b through cable_b;
  quantity angle : real;  -- [rad] drum angle
  quantity alpha : angular_acceleration;  -- drum angular acceleration
  quantity m_c   : real;  -- [N*m] torque M_c resulting from the cable forces (Eq. 4.36c)
  quantity m_cf  : real;  -- [N*m] friction torque M_cf at the gear shaft, with its sign (Eq. 4.36d)
  quantity f_cn  : force;  -- normal force F_cn pressing the gear against its shaft (Eq. 4.36e)
begin
  assert r_cd > 0.0 report "cable_drum: r_cd must be > 0" severity failure;
  assert r_gs >= 0.0 report "cable_drum: r_gs must be >= 0" severity failure;
  assert alpha_c >= 0.0 and alpha_c <= math_pi report "cable_drum: alpha_c must be in [0, pi] rad" severity failure;
  assert mu_gs >= 0.0 and mu_gs < 1.0 report "cable_drum: mu_gs must be in [0, 1)" severity failure;
  assert j_cd > 0.0 report "cable_drum: j_cd must be > 0" severity failure;
  assert omega_threshold > 0.0 report "cable_drum: omega_threshold must be > 0" severity failure;

  -- Eq. 4.36a (differentiated): both cable ends move with the drum periphery.
  v_a == r_cd * omega;
  v_b == r_cd * omega;

  -- Eq. 4.36c, e, d, b.
  m_c == r_cd * (-force_a - force_b);
  f_cn == sqrt(realmax(0.0, -force_a) ** 2 + realmax(0.0, force_b) ** 2
               - 2.0 * cos(alpha_c) * realmax(0.0, -force_a) * realmax(0.0, force_b));
  m_cf == mu_gs * f_cn * r_gs * smooth_sign(omega, omega_threshold);
  torque == m_c + m_cf + j_cd * alpha;

  alpha == omega'dot;
  angle == omega'integ;
end architecture behavioral;
