library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;

-- tb_stiffness: system-stiffness measurement by a pinch on the anti-pinch gauge (thesis 4.2.2.1,
-- Fig. 4.58-4.60, Eq. 4.42; gauge 4.3.4): the drive lifts the glass at 13 V into the force gauge hung on the
-- glass edge until the drive stalls; the trapping force is recorded by the gauge and the glass displacement
-- is converted from the motor rotation with the gear ratio and the drum radius. The resultant stiffness is
-- the slope of force over that displacement between 50 N and 100 N; Eq. 4.42 relates it to the gauge,
-- the mechanism (system stiffness) and the rubber damper in series (thesis example: 10 N/mm gauge, 0.8 N*m/deg
-- damper on a 20 mm drum radius, resultant 6.9 N/mm -> system stiffness 27.6 N/mm).
--
-- Circuit: supply (battery) -- dut (drive) -- mechanism (rail_wr, single rail, drum_diameter) -- door, with
-- gauge (antipinch_gauge, stiffness gauge_stiffness, touching at pinch_position) between glass and frame.
-- The glass starts at glass_start, below the pinch position, so the drive reaches its speed first.
-- Observables: pinch_force [N] (gauge reading), plant.dut.motor.angle [rad], plant.dut.gear.angle_g [rad], plant.mechanism.drum.angle
-- [rad], plant.door.pane.pos [m].
-- Generics: gauge_stiffness, pinch_position, glass_start, drum_diameter, u_supply.
-- bench: stiffness; parameter set: params/rail_wr_8p5nm.txt
entity tb_stiffness is
  generic (
    gauge_stiffness : stiffness := 10.0e3;  -- spring rate of the gauge (10 N/mm, European test rod)
    pinch_position  : displacement := 0.36;    -- glass position at first contact (10 mm below the top sealing)
    glass_start     : displacement := 0.30;    -- glass position at t = 0
    drum_diameter   : displacement := 0.040;   -- cable drum diameter (Eq. 4.42 example: radius 20 mm)
    u_supply        : voltage := 13.0);   -- battery voltage
end entity tb_stiffness;

architecture structural of tb_stiffness is
  signal hall_a, hall_b, hall_dir : std_logic;  -- Hall signals of the drive
  terminal supply_p   : electrical;       -- battery plus = drive plus
  terminal glass      : translational_v;  -- glass pin of mechanism, door and gauge
  quantity pinch_force : force;            -- reading of the gauge (driven by its out port)
begin
  assert pinch_position > glass_start
    report "tb_stiffness: pinch_position must be above glass_start" severity failure;

  supply: entity work.battery(structural)
    generic map (u => u_supply)
    port map (p => supply_p, n => electrical_ref);

  plant: entity work.window_regulator(structural)
    generic map (drum_diameter => drum_diameter, glass_position0 => glass_start)
    port map (p => supply_p, n => electrical_ref, glass => glass,
              hall_a => hall_a, hall_b => hall_b, direction => hall_dir);

  gauge: entity work.antipinch_gauge(behavioral)
    generic map (stiffness => gauge_stiffness, pinch_position => pinch_position, position0 => glass_start)
    port map (glass => glass, frame => translational_velocity_ref, pinch_force => pinch_force);
end architecture structural;
