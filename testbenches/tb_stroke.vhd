library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;

-- tb_stroke: open-loop window-regulator system (thesis 5.1, Fig. 5.1 without electronics): battery, drive,
-- rail mechanism and door; the glass is lifted from fully open into the top frame at a fixed voltage
-- (5.3.1, Fig. 5.7-5.9: 13 V, drum 44 mm, measured "from being completely open to being completely closed").
-- measurement: params/measurements/fig5_7_5_8_stroke.csv
--
-- Circuit: supply (battery, u_supply, from t = 0) -- dut (drive; parameters from the parameter set) --
-- mechanism (rail_wr, single rail, drum_diameter from this bench) -- door (glass, sealings, top frame; the
-- frame is the translational_v reference). At the DC operating point the drive is at rest (dcpm_motor
-- initial conditions), the glass is held on the bottom rail stop and both compressing springs have their
-- spacer compression; from t = 0 the glass is released and the drive is powered.
-- Observables: dut.motor.ia [A], dut.speed_rpm [rpm] (drive output = drum), mechanism.drum.torque [N*m],
-- mechanism.drum.angle [rad], door.pane.pos [m], door.pane.v [m/s], mechanism.spring_up.tension [N],
-- mechanism.spring_down.tension [N], mechanism.spring_up.compression [m] (tension distribution, Fig. 4.62).
-- Generics: u_supply, drum_diameter (the drum-diameter study of 5.3.3 varies it, see tb_drum_diameter).
entity tb_stroke is
  generic (
    u_supply      : real := 13.0;    -- [V] battery voltage (thesis: nominal 13 V)
    drum_diameter : real := 0.044);  -- [m] cable drum diameter (5.3.1: 44 mm; Table 5.1: 40 .. 48 mm)
end entity tb_stroke;

architecture structural of tb_stroke is
  signal hall_a, hall_b, hall_dir : std_logic;  -- Hall signals of the drive
  terminal supply_p   : electrical;       -- battery plus = drive plus (minus on the electrical reference)
  terminal drum_shaft : rotational_v;     -- drive output = cable drum
  terminal glass      : translational_v;  -- glass pin of mechanism and door
begin
  supply: entity work.battery(structural)
    generic map (u => u_supply)
    port map (p => supply_p, n => electrical_ref);

  dut: entity work.drive(structural)
    port map (p => supply_p, n => electrical_ref, shaft => drum_shaft,
             hall_a => hall_a, hall_b => hall_b, direction => hall_dir);

  mechanism: entity work.rail_wr(single_rail)
    generic map (drum_diameter => drum_diameter)
    port map (shaft => drum_shaft, glass => glass);

  door: entity work.door(structural)
    port map (glass => glass, frame => translational_velocity_ref);
end architecture structural;
