library IEEE;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_params.all;

-- rotational_spring: linear torsion spring between two shafts, e.g. the load on the gear wheel of the
-- worm-gear test bench (thesis 4.1.2.6, Fig. 4.28: "gear is loaded with rotational spring").
--
-- Equations (Hooke):  M = c*dphi     torque == stiffness * deformation
--                     dphi'dot = relative speed    deformation'dot == speed
--
-- Sign convention (passive, IEEE 1076.1.1, rotational_v): speed = speed(shaft_a) - speed(shaft_b) [rad/s],
-- deformation = angle(shaft_a) - angle(shaft_b) [rad]; torque = torque the spring takes from shaft_a and
-- passes on to shaft_b [N*m]; connect shaft_b to rotational_velocity_ref for a spring anchored in the housing. At
-- the DC operating point deformation'dot = 0 holds both ends together and the deformation carries whatever
-- static torque the network puts on it (0 when nothing loads it: the spring starts relaxed).
--
-- Generics: stiffness (> 0). Limits: no damping, no preload, no end stops (see rubber_damper for the
-- nonlinear damper of the drive, Eq. 4.28).
entity rotational_spring is
  generic (
    stiffness : angular_stiffness := rotational_spring_stiffness);  -- torsional stiffness c
  port (
    terminal shaft_a, shaft_b : rotational_v);  -- the two ends of the spring
end entity rotational_spring;

architecture linear of rotational_spring is
  -- relative speed [rad/s] of shaft_a against shaft_b; torque [N*m] from shaft_a through the spring to shaft_b
  quantity speed across torque through shaft_a to shaft_b;
  quantity deformation : angle;  -- angle(shaft_a) - angle(shaft_b)
begin
  assert stiffness > 0.0 report "rotational_spring: stiffness must be > 0" severity failure;

  torque == stiffness * deformation;
  deformation'dot == speed;
end architecture linear;
