library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;

-- tb_stroke: open-loop window-regulator system (thesis 5.1, Fig. 5.1 without electronics): battery, drive,
-- rail mechanism and door; the glass is lifted from fully open into the top frame at a fixed voltage
-- (5.3.1, Fig. 5.7-5.9: 13 V, drum 44 mm, measured "from being completely open to being completely closed").
-- bench: stroke; parameter set: params/rail_wr_8p5nm.txt
-- measurement: params/measurements/fig5_7_5_8_stroke.csv
--
-- Circuit: supply (battery, u_supply, from t = 0) -- dut (drive; parameters from the parameter set) --
-- mechanism (rail_wr, single rail, drum_diameter from this bench) -- door (glass, sealings, top frame; the
-- frame is the translational_v reference). At the DC operating point the drive is at rest (dcpm_motor
-- initial conditions), the glass is held on the bottom rail stop and both compressing springs have their
-- spacer compression; from t = 0 the glass is released and the drive is powered.
-- Observables: plant.dut.motor.ia [A], plant.dut.speed_rpm [rpm] (drive output = drum), plant.mechanism.drum.torque [N*m],
-- plant.mechanism.drum.angle [rad], plant.door.pane.pos [m], plant.door.pane.v [m/s], plant.mechanism.spring_up.tension [N],
-- plant.mechanism.spring_down.tension [N], plant.mechanism.spring_up.compression [m] (tension distribution, Fig. 4.62).
-- Generics: u_supply, drum_diameter (the drum-diameter study of 5.3.3 varies it, see tb_drum_diameter).
entity tb_stroke is
  generic (
    u_supply      : voltage := 13.0;    -- battery voltage (thesis: nominal 13 V)
    drum_diameter : displacement := 0.044);  -- cable drum diameter (5.3.1: 44 mm; Table 5.1: 40 .. 48 mm)
end entity tb_stroke;

architecture structural of tb_stroke is
  signal hall_a, hall_b, hall_dir : std_logic;  -- Hall signals of the drive
  terminal supply_p   : electrical;       -- battery plus = drive plus (minus on the electrical reference)
  terminal glass      : translational_v;  -- glass pin of mechanism and door
begin
  supply: entity work.battery(structural)
    generic map (u => u_supply)
    port map (p => supply_p, n => electrical_ref);

  plant: entity work.window_regulator(structural)
    generic map (drum_diameter => drum_diameter)
    port map (p => supply_p, n => electrical_ref, glass => glass,
              hall_a => hall_a, hall_b => hall_b, direction => hall_dir);
end architecture structural;
