library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;
use work.wr_params.all;

-- bowden: bowden cable of the rail window-regulator mechanism (thesis 4.2.1.2, Fig. 4.49/4.50), and the
-- non-rotatable (fixed) pulley, which the thesis models with the same law (4.2.1.3, type 1): the cable slips
-- over a curved path with wrap angle alpha and loses force by dry friction (capstan equation).
--
-- Equations (Eq. 4.37/4.38):
--   rigid cable: both ends move together            v_a == v_b
--   4.38a  F_a = F_b*exp(mu*alpha*sgn(V))            force_a == -force_b * exp(mu*alpha*smooth_sign(v_a, v_threshold))
--   4.38b  eta = F_b/F_a = exp(-mu*alpha*sgn(V))
--   V = cable velocity, positive when the cable moves out at A (is pulled from the A side, Eq. 4.37a).
--   sgn(V) is smoothed below v_threshold (thesis 4.1.2.4), so the force ratio passes continuously through 1
--   at standstill and a standing bowden holds any ratio between exp(-mu*alpha) and exp(mu*alpha) by creeping
--   slower than v_threshold.
--
-- Sign convention (passive, IEEE 1076.1.1; cable loop of vhdl/mechanism, velocity form): v_a = v_b = cable
-- velocity V [m/s], positive in the direction the cable moves while the glass is lifted (towards end A). force_a = F_a = the
-- tension at end A taken from cable_a; force_b = -F_b (the element passes the tension on to cable_b). The
-- friction force F_a - F_b goes to the reference (the sheath is fixed in the door).
--
-- Generics: mu (friction coefficient cable/inner tube: 0.08 at 20 .. 80 degC, 0.20 at -30 degC, Fig. 4.50),
-- alpha (wrap angle = total bending of the bowden or wrap of a fixed pulley), v_threshold.
-- Limits: rigid, massless cable (4.2.1); no shape or bending stiffness of the sheath; mu independent of load.
entity bowden is
  generic (
    mu          : real     := bowden_mu;            -- [1] friction coefficient between cable and inner tube (or fixed pulley)
    alpha       : angle    := bowden_alpha;         -- wrap angle alpha of the cable
    v_threshold : velocity := bowden_v_threshold);  -- cable speed below which sgn(V) is linear in V
  port (
    terminal cable_a, cable_b : translational_v);  -- end A (pulled out while lifting), end B
end entity bowden;

architecture capstan of bowden is
  -- cable velocities [m/s] and the forces [N] taken from the two ends (force_a = F_a, force_b = -F_b)
  quantity v_a across force_a through cable_a;
  quantity v_b across force_b through cable_b;
begin
  assert mu >= 0.0 and mu < 1.0 report "bowden: mu must be in [0, 1)" severity failure;
  assert alpha >= 0.0 report "bowden: alpha must be >= 0" severity failure;
  assert v_threshold > 0.0 report "bowden: v_threshold must be > 0" severity failure;

  v_a == v_b;
  force_a == -force_b * exp(mu * alpha * smooth_sign(v_a, v_threshold));  -- Eq. 4.38a
end architecture capstan;
