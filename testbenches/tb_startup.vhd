library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;

-- tb_startup: start-up of the window regulator upwards from the same or from the opposite direction (thesis
-- 4.2.2.2 c, Fig. 4.61/4.64). Operations 1 and 2 of Fig. 4.64 (a move down or up, then stop) leave the cable
-- loop with the tension distribution of that move: after lowering, the lower compressing spring is pressed
-- (into block) and the upper one relaxed; after lifting, the reverse. This bench starts operation 3 (up)
-- from that state, given as the mechanism's tension_state (-1.0: as left by lowering, "start from opposite
-- direction"; +1.0: as left by lifting, "start from same direction"). From the opposite direction the loop
-- first redistributes its tension (the lower spring relaxes, the upper one is pressed into block), which
-- costs the drive little torque: the speed rises to a first peak. From the same direction the drive meets
-- the load at once: no first peak. Operations 1 and 2 themselves are not simulated here: after a lifting
-- stroke the drive has to hold about 2 N*m by self-locking, and ngspice does not converge there (the worm
-- gear's self-locking creep sits at the edge of its smoothing band); the tension states are those the
-- strokes leave (tb_stroke: upper spring in block while lifting; lower spring at its block force while
-- lowering, 58 N of 60 N in a simulated downward move).
--
-- Circuit: supply (pwl_supply: 0 V, then +u_supply after ramp_time) -- dut (drive, parameters from the
-- parameter set) -- mechanism (rail_wr, single rail, tension_state) -- door. The glass starts at glass_start,
-- held at the DC operating point and released at t = 0.
-- Observables: plant.dut.speed_rpm [rpm], plant.dut.motor.ia [A], plant.mechanism.spring_up.compression and
-- plant.mechanism.spring_down.compression [m] (tension distribution, Fig. 4.64), plant.door.pane.pos [m].
-- Generics: tension_state (-1.0 / +1.0), u_supply, glass_start, ramp_time, drum_diameter.
-- bench: startup; parameter set: params/rail_wr_8p5nm.txt
entity tb_startup is
  generic (
    tension_state : real := -1.0;   -- [1] -1.0: after a lowering stroke (opposite), +1.0: after lifting (same)
    u_supply      : voltage := 13.0;   -- supply voltage
    glass_start   : displacement := 0.20;   -- glass position at t = 0 (half way up the stroke)
    ramp_time     : real := 0.002;  -- [s] duration of the voltage step of the source
    drum_diameter : displacement := 0.044); -- cable drum diameter
end entity tb_startup;

architecture structural of tb_startup is
  signal hall_a, hall_b, hall_dir : std_logic;  -- Hall signals of the drive
  terminal supply_p   : electrical;       -- supply plus = drive plus
  terminal glass      : translational_v;  -- glass pin of mechanism and door
begin
  assert tension_state = 1.0 or tension_state = -1.0
    report "tb_startup: tension_state must be 1.0 or -1.0" severity failure;
  assert ramp_time > 0.0 report "tb_startup: ramp_time must be > 0" severity failure;

  supply: entity work.pwl_supply(behavioral)
    generic map (times => (0.0, ramp_time), values => (0.0, u_supply))
    port map (p => supply_p, n => electrical_ref);

  plant: entity work.window_regulator(structural)
    generic map (drum_diameter => drum_diameter, glass_position0 => glass_start, tension_state => tension_state)
    port map (p => supply_p, n => electrical_ref, glass => glass,
              hall_a => hall_a, hall_b => hall_b, direction => hall_dir);
end architecture structural;
