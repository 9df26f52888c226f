library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_params.all;

-- glass: the window glass of the door model (thesis 4.3.1.2): a mass moving along its guided direction,
-- which is tilted against the vertical by the tilting angle; the glass geometry is not modelled (its top
-- edge moves with its lower edge, 5.1 b).
--
-- Equations (Newton along the direction of motion, velocity form):
--   F = m*dv/dt + m*g*cos(tilt)     force == m * (v'dot + g_n * cos(tilt))
--   x = position0 + integral of v   pos == position0 + v'integ   (observable glass position)
-- The gravity component along the motion is m*g*cos(tilt); the normal component, which the thesis uses to
-- size the sliders' load perpendicular to the rail (4.3.1.2), does not enter the motion.
-- Initial state: at the DC operating point (quiescent domain) the glass is held at rest (v = 0, the holding
-- force is whatever balances the mechanism and door there: with the springs at their spacer compression
-- the loop is unloaded and the hold carries the weight); from t = 0 it is released and Newton applies.
--
-- Sign convention (passive, IEEE 1076.1.1, translational_v): v = glass velocity [m/s], positive upwards
-- (closing); force = force the glass takes from its terminal [N] = the force needed to move it (m*g*cos(tilt)
-- at rest); pos = glass position [m], 0 = fully open.
--
-- Generics: m (glass mass; 2.55 kg in 5.3.1), tilt (angle between the direction of motion and the vertical),
-- position0 (glass position at t = 0).
-- Limits: rigid glass, no rotation in the sealings (Fig. 5.6: a rotating glass measures lower forces).
entity glass is
  generic (
    m         : mass         := glass_m;           -- glass mass
    tilt      : angle        := glass_tilt;        -- tilting angle of the glass's direction of motion against the vertical
    position0 : displacement := glass_position0);  -- glass position at t = 0
  port (
    terminal glass : translational_v);  -- glass (lower edge = top edge)
end entity glass;

architecture behavioral of glass is
  constant g_n : real := 9.80665;  -- [m/s**2] standard gravity
  quantity v across force through glass;  -- glass velocity [m/s] and the force [N] it takes from the terminal
  quantity pos : displacement;  -- glass position
begin
  assert m > 0.0 report "glass: m must be > 0" severity failure;
  assert abs(tilt) < 0.5 * math_pi report "glass: tilt must be in (-pi/2, pi/2) rad" severity failure;

  if domain = quiescent_domain use
    v == 0.0;
  else
    force == m * (v'dot + g_n * cos(tilt));
  end use;
  pos == position0 + v'integ;
end architecture behavioral;
