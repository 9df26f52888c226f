library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;

-- tb_motor_characteristic: performance-curve measurement of the DCPM motor (thesis 4.1.1.4, Fig. 4.8):
-- the motor is supplied with 13 V and the servo brake raises the load torque linearly from 0 to 0.5 N*m
-- in 3 s (Eq. 4.4d), from no load through the working range to stall.
-- bench: motor-characteristic; parameter set: params/fpg2_12nm.txt
-- measurement: params/measurements/fig4_15_motor.csv
-- Compared: armature speed dut.speed_rpm [rpm] and current dut.ia [A] over the brake torque
-- load.load_torque [N*m] against the mean line of Fig. 4.15 ("Speed Mean", "Current Mean"), at the
-- tabulated torques that lie within the working range of 10 % to 80 % of the stall torque (4.1.1.4).
-- The runner repeats the bench with direction = -1.0 (other sense of rotation); speed and current are then
-- negative and are compared by magnitude.
--
-- Circuit: supply (dc_supply, u = direction*u_supply) -- dut (dcpm_motor, parameters from the parameter
-- set, no generic map) -- load (torque_ramp on the armature, braking in the direction of rotation).
-- The motor starts from rest at t = 0 (dcpm_motor initial conditions); its start-up (mechanical time
-- constant of the order of 20 ms) is over long before the ramp reaches 10 % of the stall torque.
-- Generics: direction (+1/-1), u_supply, torque_end, ramp_time.
entity tb_motor_characteristic is
  generic (
    direction  : real := 1.0;   -- [1] sense of rotation: +1.0, or -1.0 for the reverse measurement
    u_supply   : voltage := 13.0;  -- magnitude of the supply voltage
    torque_end : torque := 0.5;   -- brake torque at the end of the ramp
    ramp_time  : real := 3.0);  -- [s] duration of the brake torque ramp
end entity tb_motor_characteristic;

architecture structural of tb_motor_characteristic is
  terminal supply_p    : electrical;  -- supply plus = motor plus (minus on the electrical reference)
  terminal motor_shaft : rotational_v;  -- armature coupled to the servo brake
begin
  assert direction = 1.0 or direction = -1.0
    report "tb_motor_characteristic: direction must be 1.0 or -1.0" severity failure;

  supply: entity work.dc_supply(behavioral)
    generic map (u => direction * u_supply)
    port map (p => supply_p, n => electrical_ref);

  dut: entity work.dcpm_motor(simple)
    port map (p => supply_p, n => electrical_ref, shaft => motor_shaft);

  load: entity work.torque_ramp(behavioral)
    generic map (torque_end => torque_end, ramp_time => ramp_time, direction => direction)
    port map (shaft => motor_shaft);
end architecture structural;
