library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;

-- tb_closed_loop: the closed-loop window-regulator system of thesis 5.1 (Fig. 5.1): supply, ECU hardware
-- (relays, supply digitisation) and ECU software (position counter, normalization, anti-pinch), drive with
-- its Hall sensor, rail mechanism, door, the anti-pinch gauge, and the switch that plays a sequence file.
-- Normalization 5.2.1 (Fig. 5.3), anti-pinch 5.3.2 (Fig. 5.11), CAN replay (docs/switch-sequence.md).
--
-- Two ECU concepts (ecu_kind): 0, the thesis's relay ECU (below); 1, the semiconductor ECU: bridge (h_bridge, averaged:
-- a MOSFET full bridge with PWM) between supply and motor, sense (ecu_sense: the motor current through a shunt, the
-- supply, the ADC) and control (motor_controller: speed control of the glass on the Hall speed, params/ecu/pwm.txt),
-- which turns the ECU software's relay outputs into the bridge's duty, mode and direction and gives the software the
-- mean voltage it drives the motor with (on supply_code) and the current (current_code).
-- Circuit: supply (lab_supply, u_nominal + the switch's voltage offset) -- hw (ecu_hardware: relays between
-- supply and motor, 10 mOhm per closed contact (an assumption; with ideal contacts ngspice stops with
-- "timestep too small" while the drive is stalled in the top frame), supply_code to the software) -- dut (drive; Hall A/B out) -- mechanism (rail_wr, single
-- rail, drum_diameter) -- door (glass, sealings, top frame as the translational_v reference) and gauge
-- (antipinch_gauge between glass and frame, touching at pinch_position; beyond the top frame at 0.40 m it
-- is never touched). The gauge hangs on a stand that can hold it gauge_travel above its place until
-- gauge_insert (so that a normalization run up reaches the top frame before a pinch test). ecu (ecu_software) and sw (switch) are digital units run by GHDL: Hall signals and
-- supply code in, relays and motor state out; the ECU's position vector goes to the switch, which commands
-- the ECU and offsets the supply. At the DC operating point the drive is at rest and the glass on the
-- bottom rail stop (window fully open); the ECU powers up not normalized with position 0 (by default: glass_start
-- and a warm start change both).
-- Observables: plant.door.pane.pos [m], pinch_force [N], supply.ua [V], plant.dut.motor.ia [A], plant.dut.speed_rpm [rpm],
-- position [edges] (32-bit vector, two's complement), estimate [0.1 N] (16-bit, two's complement: the anti-pinch
-- algorithm's load above its reference as a force), normalized, pinch, motor_state, command,
-- voltage_offset [0.1 V], hall_a, hall_b.
-- Generics: sequence_file (path of the switch sequence, lower case, no blanks), u_nominal, pinch_position,
-- gauge_stiffness, gauge_travel, gauge_insert, drum_diameter (the mechanism's drum only: the ECU software
-- keeps its edges_per_m for 44 mm, as a drum change in the model leaves the software alone), road_accel,
-- road_frequency, road_band_high, road_lines, road_seed, seal_change, disturbance_on (door_disturbance on the glass:
-- a rough road, sinusoidal or random, and a change of the seal friction after the normalization, for false
-- reversals; none by default), glass_start (the glass position at
-- t = 0, for the plant and the gauge), learned_file, start_position, learned_out (the ECU's warm start and the
-- file it writes its learned state to, docs/anti-pinch.md "Warm start": a warm-started run skips the
-- normalization when glass_start and start_position agree with the file's run), record_out and reverse_on_pinch (a
-- record of the ECU's inputs with the reversal held off, for tb_replay: docs/anti-pinch.md, "Record and replay"),
-- ecu_kind.
-- Limits: the ECU captures each Hall-A edge with a 1 us timer and the edge lands within 1 us of its crossing
-- (exact 'above crossings), so the speed the ECU measures carries an error of about 2 us per revolution.
-- bench: normalization, pinch, pinch-drum-diameter, compliance(-pwm), can-replay; parameter set: params/rail_wr_8p5nm.txt
entity tb_closed_loop is
  generic (
    sequence_file   : string := "switch_sequence.txt";  -- [-] switch sequence file (docs/switch-sequence.md)
    u_nominal       : voltage   := 13.0;                   -- supply voltage at voltage offset 0
    pinch_position  : displacement   := 1.0;                    -- glass position at which the gauge is touched
    gauge_stiffness : stiffness   := 10.0e3;                 -- spring rate of the gauge (10 N/mm, 4.3.4)
    gauge_travel    : displacement   := 0.0;                    -- gauge held this far above its place at t = 0
    gauge_insert    : real   := 0.0;                    -- [s] the gauge moves into place from this time
    drum_diameter   : displacement   := 0.044;                  -- cable drum diameter (5.3.3; the ECU keeps 44 mm)
    road_accel      : acceleration := 0.0;              -- door acceleration of a rough road (door_disturbance)
    road_frequency  : real   := 12.0;                   -- [Hz] its frequency (a random road: the band's lower edge)
    road_band_high  : real   := 0.0;                    -- [Hz] a random road: the band's upper edge
    road_lines      : natural := 0;                     -- [1] a random road: its sinusoids (0: one sinusoid)
    road_seed       : natural := 1;                     -- [1] a random road: its draw
    seal_change     : force  := 0.0;                    -- extra seal friction, < 0: less (door_disturbance)
    disturbance_on  : real   := 7.8;                    -- [s] both start (the pinch sequences: the first test run)
    glass_start     : displacement := 0.0;              -- glass position at t = 0 (0 = fully open)
    learned_file    : string := "";                     -- [-] the ECU's warm start from this learned state ("": cold)
    start_position  : integer := 0;                     -- [edges] the ECU's position at a warm start
    learned_out     : string := "";                     -- [-] the ECU writes its learned state here ("": not at all)
    record_out      : string := "";                     -- [-] the ECU records its inputs here ("": not at all)
    reverse_on_pinch : boolean := true;                 -- [-] false: the ECU holds a detection off (a record)
    ecu_kind        : natural := 0);                    -- [1] the ECU: 0 the thesis's relays, 1 the PWM ECU
end entity tb_closed_loop;

architecture structural of tb_closed_loop is
  terminal supply_p   : electrical;       -- supply plus (minus on the electrical reference)
  terminal mot_p, mot_n : electrical;     -- motor leads behind the relays
  terminal glass      : translational_v;  -- glass pin of mechanism, door and gauge
  terminal stand      : translational_v;  -- the gauge's stand (gauge frame side)
  quantity pinch_force : force;            -- reading of the gauge
  quantity stand_v across stand_f through stand;  -- [m/s] stand velocity, [N] force the stand takes
  signal hall_a, hall_b, hall_dir : std_logic;             -- Hall signals of the drive
  signal relay_up, relay_down     : std_logic;             -- relay coils
  signal supply_code              : std_logic_vector(7 downto 0);   -- [0.1 V] supply register
  signal command                  : std_logic_vector(1 downto 0);   -- switch -> ECU
  signal voltage_offset           : std_logic_vector(7 downto 0);   -- [0.1 V] switch -> supply
  signal position                 : std_logic_vector(31 downto 0);  -- [edges] ECU -> switch
  signal estimate                 : std_logic_vector(15 downto 0);  -- [0.1 N] ECU: the algorithm's estimate
  signal normalized, pinch        : std_logic;
  signal motor_state              : std_logic_vector(1 downto 0);
  signal battery_code             : std_logic_vector(7 downto 0);   -- [0.1 V] PWM ECU: the measured supply
  signal current_code             : std_logic_vector(9 downto 0);   -- [ADC steps] PWM ECU: the motor current
  signal duty                     : std_logic_vector(9 downto 0);   -- [1/1023] PWM ECU: the bridge's duty
  signal bridge_mode              : std_logic_vector(1 downto 0);   -- PWM ECU: the bridge's mode
  signal bridge_dir               : std_logic;                      -- PWM ECU: the bridge's direction
  terminal shunt_p                : electrical;                     -- PWM ECU: bridge side of the shunt
  constant insert_time : real := 0.5;    -- [s] duration of the gauge's move into place
begin
  assert gauge_travel >= 0.0 report "tb_closed_loop: gauge_travel must be >= 0" severity failure;
  assert drum_diameter > 0.0 report "tb_closed_loop: drum_diameter must be > 0" severity failure;
  assert ecu_kind <= 1 report "tb_closed_loop: ecu_kind must be 0 (relays) or 1 (PWM)" severity failure;

  -- The gauge stand: at rest, except that it moves the gauge down by gauge_travel into its place during
  -- insert_time from gauge_insert (the operator puts the rod in after the normalization run).
  if now > gauge_insert and now < gauge_insert + insert_time use
    stand_v == -gauge_travel / insert_time;
  else
    stand_v == 0.0;
  end use;

  supply: entity work.lab_supply(behavioral)
    generic map (u_nominal => u_nominal)
    port map (p => supply_p, n => electrical_ref, voltage_offset => voltage_offset);

  relays: if ecu_kind = 0 generate
    hw: entity work.ecu_hardware(behavioral)
      generic map (r_contact => 0.01)
      port map (bat_p => supply_p, bat_n => electrical_ref, mot_p => mot_p, mot_n => mot_n,
                relay_up => relay_up, relay_down => relay_down, supply_code => supply_code);
  end generate relays;

  pwm: if ecu_kind = 1 generate
    bridge: entity work.h_bridge(averaged)
      port map (bat_p => supply_p, bat_n => electrical_ref, mot_p => shunt_p, mot_n => mot_n,
                duty => duty, mode => bridge_mode, dir => bridge_dir);
    sense: entity work.ecu_sense(behavioral)
      port map (p => shunt_p, n => mot_p, bat_p => supply_p, bat_n => electrical_ref,
                current_code => current_code, supply_code => battery_code);
    control: entity work.motor_controller
      port map (hall_a => hall_a, hall_b => hall_b, supply_code => battery_code, current_code => current_code,
                run_up => relay_up, run_down => relay_down, position => position, normalized => normalized,
                duty => duty, mode => bridge_mode, dir => bridge_dir, effort => supply_code);
  end generate pwm;

  plant: entity work.window_regulator(structural)
    generic map (drum_diameter => drum_diameter, glass_position0 => glass_start)
    port map (p => mot_p, n => mot_n, glass => glass,
              hall_a => hall_a, hall_b => hall_b, direction => hall_dir);

  gauge: entity work.antipinch_gauge(behavioral)
    generic map (stiffness => gauge_stiffness, pinch_position => pinch_position,
                 position0 => glass_start - gauge_travel)
    port map (glass => glass, frame => stand, pinch_force => pinch_force);

  disturbance: entity work.door_disturbance(behavioral)
    generic map (accel => road_accel, frequency => road_frequency, band_high => road_band_high, lines => road_lines,
                 seed => road_seed, friction => seal_change, t_on => disturbance_on)
    port map (glass => glass, frame => translational_velocity_ref);

  ecu: entity work.ecu_software
    generic map (learned_file => learned_file, start_position => start_position, learned_out => learned_out,
                 record_out => record_out, reverse_on_pinch => reverse_on_pinch)
    port map (hall_a => hall_a, hall_b => hall_b, supply_code => supply_code, current_code => current_code,
              command => command, relay_up => relay_up, relay_down => relay_down, position => position,
              normalized => normalized, pinch => pinch, motor_state => motor_state, estimate => estimate);

  sw: entity work.switch
    generic map (sequence_file => sequence_file)
    port map (position => position, command => command, voltage_offset => voltage_offset);
end architecture structural;
