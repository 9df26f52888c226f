library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_params.all;

-- antipinch_gauge: anti-pinch force measurement gauge (thesis 4.3.4, Fig. 4.77): a spring-like test rod
-- hung on the glass edge; when the rod touches the door frame a pinch event is imitated and the pinch force
-- is measured. Three pins as in the thesis: glass, frame (the sealing/upper door frame), and the pinch force
-- as an out quantity.
--
-- Equations (c = stiffness, x_p = pinch_position, beta = pinch_angle between the rod and the glass motion;
-- velocity form, x = position0 + integral of the glass velocity):
--   rod deflection     delta = max(0, (x - x_p)*cos(beta))     the rod touches at glass position x_p
--   pinch force        F_p   = c*delta                          pinch_force == stiffness * deflection
--   force on the glass F     = F_p*cos(beta)                    force == pinch_force * cos(pinch_angle)
--   (the rod is compressed along its own axis; only the component along the glass motion loads the glass)
--
-- Sign convention (passive, IEEE 1076.1.1, translational_v): v = glass velocity against the frame [m/s]
-- (positive up), pos = glass position [m];
-- force = force the gauge takes from the glass [N] (> 0: it pushes the glass down); pinch_force >= 0 [N] is
-- the reading of the gauge.
--
-- Generics: stiffness (legal test springs: 10 N/mm in Europe, 20 or 65 N/mm in the USA; 5 N/mm also in
-- Fig. 4.77), pinch_position (glass position at first contact; above the top frame = no pinch, the normal
-- runs of 5.2.1), pinch_angle (from CAD, 4.3.4), position0 (glass position at t = 0).
-- Limits: linear spring, no damping, no hysteresis; the touch at pinch_position is a kink of the force law,
-- written as pos'above(pinch_position) with break on it, so that the solver puts a time point on the touch;
-- stiffness at most 1e6 N/m (1000 N/mm, a rigid block, 15 times the stiffest legal rod): far stiffer rods are no
-- test device, and the closed loop's solver settings are not made for them (a 2.1e12 N/m rod stopped the transient
-- with "timestep too small").
entity antipinch_gauge is
  generic (
    stiffness      : stiffness    := antipinch_gauge_stiffness;       -- spring rate of the gauge
    pinch_position : displacement := antipinch_gauge_pinch_position;  -- glass position at which the rod touches the frame
    pinch_angle    : angle        := antipinch_gauge_pinch_angle;     -- angle between the rod (pinch force) and the glass motion
    position0      : displacement := antipinch_gauge_position0);      -- glass position at t = 0
  port (
    terminal glass, frame   : translational_v;  -- glass edge, upper door frame (sealing)
    quantity pinch_force : out real);         -- [N] measured pinch force
end entity antipinch_gauge;

architecture behavioral of antipinch_gauge is
  quantity v across force through glass to frame;  -- glass velocity [m/s], force [N] taken from the glass
  quantity pos        : displacement;  -- glass position
  quantity deflection : displacement;  -- compression of the gauge's spring along its axis
begin
  assert stiffness > 0.0 and stiffness <= 1.0e6
    report "antipinch_gauge: stiffness must be > 0 and at most 1e6 N/m (1000 N/mm)" severity failure;
  assert abs(pinch_angle) < 0.5 * math_pi
    report "antipinch_gauge: pinch_angle must be in (-pi/2, pi/2) rad" severity failure;

  pos == position0 + v'integ;
  -- The touch is a kink of the force law: a time point at the crossing, and the solver restarts there.
  if pos'above(pinch_position) use
    deflection == (pos - pinch_position) * cos(pinch_angle);
  else
    deflection == 0.0;
  end use;
  break on pos'above(pinch_position);
  pinch_force == stiffness * deflection;
  force == pinch_force * cos(pinch_angle);
end architecture behavioral;
