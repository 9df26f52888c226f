library IEEE;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_params.all;

-- door: mechanical model of the car door as seen by the window regulator (thesis 4.3.1, 5.1 b): the glass
-- (mass and tilting angle, 4.3.1.2), the sealing friction along the stroke (piecewise in the glass
-- position, 4.3.1.1) and the top-frame sealing with its three intrusion ranges and the metal frame.
-- Structural: the parts take their parameters from the parameter set's sections [glass], [seal_friction],
-- [top_frame_seal]; the door passes only the start position on (a state of the bench, not a parameter).
--
-- Pins (5.1 b): glass = the glass, connected to the mechanism's glass pin (the glass's top edge has the
-- position of its lower edge, the geometry is not modelled); frame = the upper door frame (normally the
-- translational_v reference). An anti-pinch gauge is connected between the same two pins (4.3.4).
--
-- Sign convention (passive, IEEE 1076.1.1, translational_v): glass velocity positive upwards, position 0 =
-- fully open; the door takes from the glass pin the force needed to move the glass (gravity, inertia,
-- sealing friction and frame). Observable glass position: pane.pos [m].
--
-- Generics: position0 (glass position at t = 0).
entity door is
  generic (
    position0 : displacement := door_position0);  -- glass position at t = 0
  port (
    terminal glass, frame : translational_v);  -- glass (to the mechanism and gauge), upper door frame
end entity door;

architecture structural of door is
begin
  pane: entity work.glass(behavioral)
    generic map (position0 => position0)
    port map (glass => glass);
  sealing: entity work.seal_friction(behavioral)
    generic map (position0 => position0)
    port map (glass => glass, frame => frame);
  top_seal: entity work.top_frame_seal(behavioral)
    generic map (position0 => position0)
    port map (glass => glass, frame => frame);
end architecture structural;
