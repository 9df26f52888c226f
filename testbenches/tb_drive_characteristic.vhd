library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;

-- tb_drive_characteristic: characteristic-curve measurement of the window-regulator drive (thesis 4.1.4.2,
-- Fig. 4.37): the drive is supplied with 13 V (rated voltage), runs up to no-load speed, and the test
-- stand raises the torque on the output linearly up to stall (about 13 N*m, one measurement takes about
-- 2 s).
-- bench: drive-characteristic, identification; parameter set: params/fpg2_12nm.txt
-- measurement: params/measurements/fig4_44_drive.csv
-- Compared: gear-wheel speed dut.gear.omega_g [rad/s] (converted to rpm) and current dut.motor.ia [A]
-- over the brake torque load.load_torque [N*m] against the fitting of Fig. 4.44 ("Velocity gear fitting",
-- "Current") at the tabulated torques 1 .. 5 N*m (inside the working range 1 .. 6 N*m). The thesis
-- compares gear-wheel speeds (Fig. 4.35 text); the output-shaft speed dut.speed_rpm [rpm] is lower during
-- the ramp by the rubber damper's deformation rate (about 1 .. 1.5 rpm with the default damper table).
-- The runner repeats the bench with direction = -1.0; speed and current are then compared by magnitude.
--
-- Circuit: supply (dc_supply, u = direction*u_supply) -- dut (drive, parameters from the parameter set,
-- no generic map) -- load (torque_ramp on the drive output, braking in the direction of rotation).
-- At and beyond the drive's stall torque the drive stalls and the self-locking worm gear (eta <= 0.5)
-- holds the brake torque (creeping at less than the worm gear's omega_threshold); not evaluated.
-- Generics: direction (+1/-1), u_supply, torque_end, ramp_time.
entity tb_drive_characteristic is
  generic (
    direction  : real := 1.0;   -- [1] sense of rotation: +1.0, or -1.0 for the reverse measurement
    u_supply   : voltage := 13.0;  -- magnitude of the supply voltage
    torque_end : torque := 13.0;  -- brake torque at the end of the ramp (about the stall torque)
    ramp_time  : real := 2.0);  -- [s] duration of the brake torque ramp
end entity tb_drive_characteristic;

architecture structural of tb_drive_characteristic is
  signal hall_a, hall_b, hall_dir : std_logic;  -- Hall signals of the drive
  terminal supply_p    : electrical;  -- supply plus = drive plus (minus on the electrical reference)
  terminal drive_shaft : rotational_v;  -- drive output coupled to the test-stand brake
begin
  assert direction = 1.0 or direction = -1.0
    report "tb_drive_characteristic: direction must be 1.0 or -1.0" severity failure;

  supply: entity work.dc_supply(behavioral)
    generic map (u => direction * u_supply)
    port map (p => supply_p, n => electrical_ref);

  dut: entity work.drive(structural)
    port map (p => supply_p, n => electrical_ref, shaft => drive_shaft,
             hall_a => hall_a, hall_b => hall_b, direction => hall_dir);

  load: entity work.torque_ramp(behavioral)
    generic map (torque_end => torque_end, ramp_time => ramp_time, direction => direction)
    port map (shaft => drive_shaft);
end architecture structural;
