library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;

-- tb_worm_gear_self_locking: verification of the worm gear's self-locking function (thesis 4.1.2.6,
-- Fig. 4.28/4.29). The worm is driven by a DCPM motor (0.35 N*m stall torque, 5800 rpm no load, 23 A stall
-- current: parameter set params/self_locking_bench.txt), the gear wheel (ratio 1:73) is loaded by a
-- rotational spring anchored in the housing, and the motor is fed by a piecewise-linear source:
-- +u_supply for t_on, off (0 V) for t_off, -u_supply for t_on, off until the end of the run.
-- The runner simulates it with eta = 0.46 (self-locking expected: while unpowered the gear holds its angle
-- against the spring) and with eta > 0.5 (the spring back-drives gear and motor during the pauses).
--
-- Circuit: supply (pwl_supply) -- dut (dcpm_motor) -- armature -- gear (worm_gear(behavioral), ratio 73,
-- eta) -- gear_wheel -- load (rotational_spring to the housing).
-- Spring stiffness: the thesis gives none. 0.3 N*m/rad winds the spring to about half of the drive's stall
-- torque (0.35 N*m * 73 * 0.46 = 11.8 N*m) during the first 4 s, so the gear is driven well inside its
-- working range and the spring is strongly loaded when the power goes off.
-- Judged (tools/wrsim/benches/worm_gear.py) in each unpowered window once the motor has stopped: with
-- eta = 0.46 the gear angle may change by at most omega_threshold*duration -- the creep the smoothed
-- Coulomb friction allows, the model's meaning of "holds" -- and the creep speed must follow the closed form
-- of that law; with eta = 0.55 the gear must turn back at the closed-form back-driving speed.
-- Observables: dut.angle, dut.omega (armature, Fig. 4.29), gear.angle_g, gear.omega_g, load.torque.
-- Generics: eta, u_supply, stiffness, t_on, t_off, ramp_time (duration of each voltage ramp).
-- bench: worm-gear-self-locking; parameter set: params/self_locking_bench.txt
entity tb_worm_gear_self_locking is
  generic (
    eta       : real              := 0.46;   -- [1] forward efficiency of the worm gear
    u_supply  : voltage              := 13.0;   -- magnitude of the supply voltage
    stiffness : angular_stiffness := 0.3;    -- torsional stiffness of the load spring on the gear wheel
    t_on      : real              := 4.0;    -- [s] duration of each powered phase
    t_off     : real              := 1.0;    -- [s] pause between the two powered phases
    ramp_time : real              := 0.01);  -- [s] duration of each voltage ramp of the source
end entity tb_worm_gear_self_locking;

architecture structural of tb_worm_gear_self_locking is
  terminal supply_p   : electrical;  -- supply plus = motor plus (minus on the electrical reference)
  terminal armature   : rotational_v;  -- motor armature = worm shaft
  terminal gear_wheel : rotational_v;  -- gear wheel = spring end (the other end is the housing)
begin
  assert ramp_time > 0.0 and ramp_time < t_off
    report "tb_worm_gear_self_locking: ramp_time must be > 0 and < t_off" severity failure;

  supply: entity work.pwl_supply(behavioral)
    generic map (
      times  => (0.0, ramp_time, t_on, t_on + ramp_time, t_on + t_off, t_on + t_off + ramp_time,
                 2.0 * t_on + t_off, 2.0 * t_on + t_off + ramp_time),
      values => (0.0, u_supply, u_supply, 0.0, 0.0, -u_supply, -u_supply, 0.0))
    port map (p => supply_p, n => electrical_ref);

  dut: entity work.dcpm_motor(simple)
    port map (p => supply_p, n => electrical_ref, shaft => armature);

  gear: entity work.worm_gear(behavioral)
    generic map (ratio => 73.0, eta => eta)
    port map (worm => armature, gear => gear_wheel);

  load: entity work.rotational_spring(linear)
    generic map (stiffness => stiffness)
    port map (shaft_a => gear_wheel, shaft_b => rotational_velocity_ref);
end architecture structural;
