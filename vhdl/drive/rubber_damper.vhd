library IEEE;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;
use work.wr_params.all;

-- rubber_damper: the rubber damper inside the gear wheel (thesis 4.1.3), a rotational spring whose
-- stiffness depends on the deformation through a look-up table (Eq. 4.28, Tab. 4.7, Fig. 4.32).
--
-- Equation (Eq. 4.28):  M_rd = c(dphi_d) * dphi_d
--   torque == table_lookup(abs(deformation), angles, stiffness) * deformation
--   deformation'dot == speed (relative speed of the two shafts, rotational_v)
--   c is interpolated piecewise linearly over the table and held constant beyond its ends (wr_common).
--   The same table serves both directions: the thesis measured no difference between left and right
--   rotation (Fig. 4.33), so c depends on |deformation| and the torque is odd in the deformation.
--
-- Sign convention (passive, IEEE 1076.1.1, rotational_v): speed = speed(shaft_a) - speed(shaft_b)
-- [rad/s], deformation = its integral [rad]; torque = torque the damper takes from shaft_a and passes on to
-- shaft_b [N*m]. In the drive, shaft_a is the gear wheel and shaft_b the output shaft: a load braking the
-- output gives deformation > 0, torque > 0. At the DC operating point deformation'dot = 0 makes the two
-- shafts turn together and leaves the deformation to the static torque it carries.
--
-- Generics: angles = deformation breakpoints (strictly increasing, first = 0), stiffness = secant
-- stiffness c = M_rd/dphi_d at each breakpoint (> 0), same length. Defaults: 0 .. 10 deg in 2 deg steps,
-- about 1 N*m/deg, the order the thesis states (1 .. 5 N*m deform the damper by 1 .. 6 deg, 4.1.4.1); the
-- measured table of Fig. 4.32 (converted deg -> rad, N*m/deg -> N*m/rad) belongs in a parameter set, as do
-- the other temperatures of Fig. 4.33.
-- Limits: purely elastic (no damping, no hysteresis), no end stop beyond the table. The torque must rise
-- with the deformation (c + dphi*dc/dphi > 0) for a unique static solution; the default table does.
entity rubber_damper is
  generic (
    angles    : real_vector := rubber_damper_angles;      -- [rad] deformation breakpoints of the stiffness table
    stiffness : real_vector := rubber_damper_stiffness);  -- [N*m/rad] stiffness c at each breakpoint
  port (
    terminal shaft_a, shaft_b : rotational_v);  -- gear-wheel side, output-shaft side
end entity rubber_damper;

architecture behavioral of rubber_damper is
  -- relative speed [rad/s] of shaft_a against shaft_b; torque M_rd [N*m] from shaft_a to shaft_b
  quantity speed across torque through shaft_a to shaft_b;
  quantity deformation : angle;  -- deformation dphi_d = angle(shaft_a) - angle(shaft_b)

begin
  assert angles'length = stiffness'length
    report "rubber_damper: angles and stiffness must have the same length" severity failure;
  assert angles(angles'low) = 0.0
    report "rubber_damper: angles must start at 0" severity failure;
  assert strictly_increasing(angles)
    report "rubber_damper: angles must be strictly increasing" severity failure;
  assert all_positive(stiffness)
    report "rubber_damper: stiffness values must be > 0" severity failure;

  -- Eq. 4.28
  torque == table_lookup(abs(deformation), angles, stiffness) * deformation;
  deformation'dot == speed;
end architecture behavioral;
