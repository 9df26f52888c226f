library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;
use work.wr_params.all;

-- pulley: rotatable pulley of the rail window-regulator mechanism (thesis 4.2.1.3 type 2, Fig. 4.51/4.52):
-- the cable does not slip on the pulley; the pulley turns on its shaft and the friction between pulley and
-- shaft, pressed by the resultant of the two cable forces, costs cable force. (A non-rotatable pulley is a
-- `bowden` instance with the pulley's wrap angle, thesis 4.2.1.3 type 1.)
--
-- Equations (Eq. 4.39):
--   rigid cable: both sides move together            v_a == v_b
--   4.39a  F_a = F_b + F_f
--   4.39b  F_f = F_n*mu*sgn(V)*r_in/r_out
--   4.39c  F_n = sqrt(F_a**2 + F_b**2 - 2*cos(alpha)*F_a*F_b)
--          force_a + force_b == mu * r_in / r_out * f_n * smooth_sign(v_a, v_threshold)   (F_a = force_a, F_b = -force_b)
--   4.39d  eta = F_b/F_a (0.96 measured at alpha = 162 deg, 40 mm / 12 mm, giving mu = 0.069)
--   V = cable velocity, positive when the cable moves from B to A (A = driving side, Fig. 4.51); sgn(V) is
--   smoothed below v_threshold (thesis 4.1.2.4). The pulley's mass is neglected (4.2.1.3 a).
--
-- Sign convention (passive, IEEE 1076.1.1; cable loop of vhdl/mechanism, velocity form): as `bowden`:
-- v_a = v_b = cable velocity V [m/s], positive towards A; force_a = F_a, force_b = -F_b.
--
-- Generics: mu (pulley/shaft, guided 0.04 .. 0.15, 0.069 measured), r_in (shaft radius), r_out (cable
-- wrapping radius), alpha (wrap angle: 180 deg = cable turned back, F_n = F_a + F_b), v_threshold.
-- Limits: rigid, massless cable and pulley; mu*r_in/r_out < 1 (otherwise the pulley cannot turn).
entity pulley is
  generic (
    mu          : real         := pulley_mu;            -- [1] friction coefficient between pulley and its shaft
    r_in        : displacement := pulley_r_in;          -- radius of the pulley shaft r_in
    r_out       : displacement := pulley_r_out;         -- wrapping radius of the cable over the pulley r_out
    alpha       : angle        := pulley_alpha;         -- wrap angle alpha of the cable (162 deg)
    v_threshold : velocity     := pulley_v_threshold);  -- cable speed below which sgn(V) is linear in V
  port (
    terminal cable_a, cable_b : translational_v);  -- side A (driving side while lifting), side B (driven side)
end entity pulley;

architecture behavioral of pulley is
  -- cable velocities [m/s] and the forces [N] taken from the two sides (force_a = F_a, force_b = -F_b)
  quantity v_a across force_a through cable_a;
  quantity v_b across force_b through cable_b;
  quantity f_n : force;  -- normal force F_n on the pulley shaft (Eq. 4.39c)
begin
  assert mu >= 0.0 and mu < 1.0 report "pulley: mu must be in [0, 1)" severity failure;
  assert r_in > 0.0 report "pulley: r_in must be > 0" severity failure;
  assert r_out > r_in report "pulley: r_out must be > r_in" severity failure;
  assert alpha >= 0.0 and alpha <= math_2_pi report "pulley: alpha must be in [0, 2*pi] rad" severity failure;
  assert v_threshold > 0.0 report "pulley: v_threshold must be > 0" severity failure;

  v_a == v_b;
  f_n == sqrt(force_a ** 2 + force_b ** 2 + 2.0 * cos(alpha) * force_a * force_b);   -- Eq. 4.39c, F_b = -force_b
  force_a + force_b == mu * r_in / r_out * f_n * smooth_sign(v_a, v_threshold);    -- Eq. 4.39a/b
end architecture behavioral;
