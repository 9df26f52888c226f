library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;
use work.wr_params.all;

-- window_regulator: the plant of the electrical window regulator system (thesis 5.1, Fig. 5.1 without the
-- electronics): the drive (DCPM motor, worm gear, rubber damper, housing friction, Hall sensor; 4.1), the
-- rail-guided cable mechanism (cable drum, bowdens, pulleys, compressing springs, slider; 4.2) and the door
-- (glass, seal friction, top-frame seal; 4.3). One structural entity, so that every system testbench (open
-- loop, closed loop, pinch) simulates the same plant.
--
-- Ports: p, n: the motor leads (electrical; the electronics or a supply drive them); glass: the glass pin
-- (translational_v, positive up) where a pinch gauge or a force probe attaches; hall_a, hall_b, direction:
-- the Hall signals of the drive (thesis 5.1: the sensor is packed in the drive). The upper door frame is the
-- translational_v reference.
-- Generics: drum_diameter (cable drum, 5.3.3: 40 .. 48 mm), glass_position0 (glass position at t = 0; the
-- mechanism and the door start there), tension_state (-1 .. 1: tension distribution of the cable loop at
-- t = 0, as left by a lowering (-1) or lifting (+1) stroke, 4.2.2.2). Everything else comes from the
-- parameter set of the bench, by entity name ([dcpm_motor], [worm_gear], [rail_wr], [door], ...).
-- Instances: dut (drive), mechanism (rail_wr, single rail), door.
-- Limits: those of the instantiated models (see their headers); single-rail mechanism only.
entity window_regulator is
  generic (
    drum_diameter   : displacement := window_regulator_drum_diameter;    -- cable drum diameter
    glass_position0 : displacement := window_regulator_glass_position0;  -- glass position at t = 0 (0 = fully open)
    tension_state   : real         := window_regulator_tension_state);   -- [1] tension distribution of the cable loop at t = 0
  port (
    terminal p, n         : electrical;       -- motor leads (plus, minus)
    terminal glass        : translational_v;  -- glass pin (mechanism, door, and a gauge if any)
    signal hall_a, hall_b : out std_logic;    -- Hall signals of the armature
    signal direction      : out std_logic);   -- '1' while the armature turns positive (lifting)
end entity window_regulator;

architecture structural of window_regulator is
  terminal drum_shaft : rotational_v;  -- drive output = cable drum
begin
  assert drum_diameter > 0.0 report "window_regulator: drum_diameter must be > 0" severity failure;
  assert abs(tension_state) <= 1.0 report "window_regulator: tension_state must be in [-1, 1]" severity failure;

  dut: entity work.drive(structural)
    port map (p => p, n => n, shaft => drum_shaft, hall_a => hall_a, hall_b => hall_b, direction => direction);

  mechanism: entity work.rail_wr(single_rail)
    generic map (drum_diameter => drum_diameter, glass_position0 => glass_position0, tension_state => tension_state)
    port map (shaft => drum_shaft, glass => glass);

  door: entity work.door(structural)
    generic map (position0 => glass_position0)
    port map (glass => glass, frame => translational_velocity_ref);
end architecture structural;
