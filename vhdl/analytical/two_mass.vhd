library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;
use work.wr_params.all;

-- two_mass: analytical two-mass model of the window-regulator system (thesis 3.1.1, Fig. 3.1): M_1 is the
-- equivalent mass of the armature inertia (Eq. 3.24), M_2 the glass, coupled by the system stiffness c and
-- the damping factor mu; a harmonic force F_a*sin(omega*t) drives M_1 and a dry friction force of amplitude
-- F_r acts on M_2. The forces F_a and F_r belong to the model, as in Eq. 3.2 / 3.13; the two masses are
-- translational terminals, so further elements can act on them (a terminal connected to nothing else
-- carries no external force, and the model is exactly Eq. 3.2 / 3.13).
--
-- Equations (exact system):
--   3.2a/3.13a  M_1*x1'' + c*(x1 - x2) + mu*(x1' - x2') = F_a*sin(omega*t)  (+ external force f_ext1)
--                 m1*a1 + c*(x1 - x2) + mu*(v1 - v2) == f_a*sin(omega*now) + f_ext1
--   3.2b/3.13b  M_2*x2'' + c*(x2 - x1) + mu*(x2' - x1') = -F_r*sgn(v_f)    (+ external force f_ext2)
--                 m2*a2 + c*(x2 - x1) + mu*(v2 - v1) == -f_fric + f_ext2
--   friction case 1 (3.1.2.1, Eq. 3.2b):  v_f = x2' - x1' (relative velocity; relative_friction = true)
--   friction case 2 (3.1.2.2, Eq. 3.13b): v_f = x2'      (velocity of M_2;   relative_friction = false)
--                 f_fric == f_r*smooth_sign(v_f, v_threshold)
--   sgn is smoothed below v_threshold (linear there), like every friction of the library (4.1.2.4).
--   z = x2 - x1 is the relative displacement whose amplitude the method of averaging predicts (Eq. 3.12).
--
-- Initial state (quiescent domain): relative displacement z0, centre of mass at 0, both masses at rest,
-- i.e. x1 = -M_2/(M_1 + M_2)*z0, x2 = M_1/(M_1 + M_2)*z0 -- the thesis's a(0) = 0.01, xi(0) = 0, V(0) = 0
-- is z0 = 0.01*L (3.1.2.3). From the first time step on the derivative relations apply.
--
-- Sign convention (passive, IEEE 1076.1.1): x1, x2 = positions of M_1, M_2 (terminals mass_1, mass_2)
-- against the inertial reference [m], positive in the direction of F_a; f_ext1, f_ext2 = force the model
-- takes from each terminal [N], i.e. the force the connected elements apply to that mass (a force source
-- pushing a mass forward has a negative through quantity, so f_ext > 0); f_fric = friction force on M_2
-- opposing v_f [N].
--
-- Generics: m1, m2, c, mu, f_a, omega, f_r (3.1.2.3), relative_friction (friction case), z0 (initial
-- relative displacement), v_threshold (smoothing of sgn). Defaults: the thesis's case 1.
-- Limits: linear spring and damper, no stiction (the smoothed sgn makes a stuck mass creep below
-- v_threshold), constant force amplitudes.
entity two_mass is
  generic (
    m1                : mass         := two_mass_m1;                 -- equivalent mass of the motor armature M_1
    m2                : mass         := two_mass_m2;                 -- glass mass M_2
    c                 : stiffness    := two_mass_c;                  -- system stiffness c
    mu                : damping      := two_mass_mu;                 -- damping factor mu
    f_a               : force        := two_mass_f_a;                -- amplitude F_a of the harmonic driving force on M_1
    omega             : real         := two_mass_omega;              -- [1/s] angular frequency of the driving force
    f_r               : force        := two_mass_f_r;                -- amplitude F_r of the dry friction force on M_2
    relative_friction : boolean      := two_mass_relative_friction;  -- true: friction on x2' - x1' (Eq. 3.2); false: on x2' (Eq. 3.13)
    z0                : displacement := two_mass_z0;                 -- initial relative displacement x2 - x1
    v_threshold       : velocity     := two_mass_v_threshold);       -- speed below which the friction force is linear in v_f
  port (
    terminal mass_1, mass_2 : translational);  -- the armature-equivalent mass M_1 and the glass M_2
end entity two_mass;

architecture exact of two_mass is
  -- displacement x_1* of M_1 [m] and the external force [N] the model takes from terminal mass_1
  quantity x1 across f_ext1 through mass_1;
  -- displacement x_2* of M_2 [m] and the external force [N] the model takes from terminal mass_2
  quantity x2 across f_ext2 through mass_2;
  quantity v1     : velocity;  -- velocity of M_1
  quantity v2     : velocity;  -- velocity of M_2
  quantity a1     : acceleration;  -- acceleration of M_1
  quantity a2     : acceleration;  -- acceleration of M_2
  quantity z      : displacement;  -- relative displacement x_2* - x_1*
  quantity f_fric : force;  -- dry friction force on M_2 (opposing v_f)
begin
  assert m1 > 0.0 report "two_mass: m1 must be > 0" severity failure;
  assert m2 > 0.0 report "two_mass: m2 must be > 0" severity failure;
  assert c > 0.0 report "two_mass: c must be > 0" severity failure;
  assert mu >= 0.0 report "two_mass: mu must be >= 0" severity failure;
  assert omega > 0.0 report "two_mass: omega must be > 0" severity failure;
  assert f_r >= 0.0 report "two_mass: f_r must be >= 0" severity failure;
  assert v_threshold > 0.0 report "two_mass: v_threshold must be > 0" severity failure;

  -- Eq. 3.2a / 3.13a and 3.2b / 3.13b
  m1 * a1 + c * (x1 - x2) + mu * (v1 - v2) == f_a * sin(omega * now) + f_ext1;
  m2 * a2 + c * (x2 - x1) + mu * (v2 - v1) == -f_fric + f_ext2;

  if relative_friction use
    f_fric == f_r * smooth_sign(v2 - v1, v_threshold);  -- Eq. 3.2b
  else
    f_fric == f_r * smooth_sign(v2, v_threshold);       -- Eq. 3.13b
  end use;

  z == x2 - x1;

  -- Initial state and state derivatives.
  if domain = quiescent_domain use
    x1 == -m2 / (m1 + m2) * z0;
  else
    x1'dot == v1;
  end use;
  if domain = quiescent_domain use
    x2 == m1 / (m1 + m2) * z0;
  else
    x2'dot == v2;
  end use;
  if domain = quiescent_domain use
    v1 == 0.0;
  else
    v1'dot == a1;
  end use;
  if domain = quiescent_domain use
    v2 == 0.0;
  else
    v2'dot == a2;
  end use;
end architecture exact;
