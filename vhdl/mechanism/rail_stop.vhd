library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_params.all;

-- rail_stop: stroke limit of the guide rail (thesis 4.2.1.6 a, second point: "when glass moves down into the
-- door, the bottom of the rail stops the slider. In return, it stops glass ... simulated with a stop
-- model"). A stop acts as a stiff spring against the reference (the rail) once the glass leaves
-- [position_min, position_max]; it is connected to the mechanism's glass pin, so positions are glass
-- positions (slider and glass are rigidly coupled).
--
-- Equations:
--   position  x = position0 + integral of v dt           pos == position0 + v'integ
--   force     F = stiffness*(min(0, x - position_min) + max(0, x - position_max))
--
-- Sign convention (passive, IEEE 1076.1.1, translational_v): v = glass velocity [m/s] (positive upwards);
-- force = force taken from the glass pin [N] (< 0 at the bottom stop: the stop pushes the glass up).
--
-- Generics: position0 (glass position at t = 0, the bench's start position), position_min, position_max
-- (stroke ends; the top is normally not reached because the door frame stops the glass first, default
-- real'high = no top stop), stiffness (> 0).
-- Limits: no damping, no restitution model.
entity rail_stop is
  generic (
    position0    : displacement := rail_stop_position0;     -- glass position at t = 0
    position_min : displacement := rail_stop_position_min;  -- lower end of the travel (window fully open)
    position_max : displacement := rail_stop_position_max;  -- upper end of the travel
    stiffness    : stiffness    := rail_stop_stiffness);    -- stop stiffness
  port (
    terminal glass : translational_v);  -- glass pin of the mechanism
end entity rail_stop;

architecture behavioral of rail_stop is
  quantity v across force through glass;  -- glass velocity [m/s] and the stop force [N] taken from it
  quantity pos : displacement;  -- glass position
begin
  assert position_max > position_min report "rail_stop: position_max must be > position_min" severity failure;
  assert stiffness > 0.0 report "rail_stop: stiffness must be > 0" severity failure;

  pos == position0 + v'integ;
  force == stiffness * (realmin(0.0, pos - position_min) + realmax(0.0, pos - position_max));
end architecture behavioral;
