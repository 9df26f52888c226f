-- wr_params: the default value of every generic of the analog (VHDL-AMS) models, one constant per
-- generic, named <entity>_<generic>; each entity's generic list reads its defaults from here
-- (`ke : real := dcpm_motor_ke`). The values are the thesis's (Appendix A, the tables of chapter 4) unless
-- the comment says otherwise; the comment is the generic's own (unit in brackets where the type has none).
-- A parameter set (params/*.txt) replaces these values. For another simulator, `wrsim export --params SET`
-- writes this package with the set's values: analyse that file into library WORK instead of this one,
-- after the IEEE packages and before the models (README, "Import into Saber or SystemVision").
-- Keep one constant per line, `constant <entity>_<generic> : <type> := <value>;`: the export replaces lines.
library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;

package wr_params is
  -- two_mass (vhdl/analytical/two_mass.vhd)
  constant two_mass_m1                : mass         := 45.0;    -- equivalent mass of the motor armature M_1
  constant two_mass_m2                : mass         := 5.0;     -- glass mass M_2
  constant two_mass_c                 : stiffness    := 2.0e4;   -- system stiffness c
  constant two_mass_mu                : damping      := 80.0;    -- damping factor mu
  constant two_mass_f_a               : force        := 200.0;   -- amplitude F_a of the harmonic driving force on M_1
  constant two_mass_omega             : real         := 75.8;    -- [1/s] angular frequency of the driving force
  constant two_mass_f_r               : force        := 10.0;    -- amplitude F_r of the dry friction force on M_2
  constant two_mass_relative_friction : boolean      := true;    -- true: friction on x2' - x1' (Eq. 3.2); false: on x2' (Eq. 3.13)
  constant two_mass_z0                : displacement := 0.0;     -- initial relative displacement x2 - x1
  constant two_mass_v_threshold       : velocity     := 1.0e-3;  -- speed below which the friction force is linear in v_f

  -- door (vhdl/door/door.vhd)
  constant door_position0 : displacement := 0.0;  -- glass position at t = 0

  -- glass (vhdl/door/glass.vhd)
  constant glass_m         : mass         := 2.55;  -- glass mass
  constant glass_tilt      : angle        := 0.0;   -- tilting angle of the glass's direction of motion against the vertical
  constant glass_position0 : displacement := 0.0;   -- glass position at t = 0

  -- seal_friction (vhdl/door/seal_friction.vhd)
  constant seal_friction_positions   : real_vector  := (0.0, 0.37);   -- [m] glass positions of the friction table, strictly increasing
  constant seal_friction_forces      : real_vector  := (15.0, 40.0);  -- [N] friction force magnitude at each position
  constant seal_friction_v_threshold : velocity     := 1.0e-3;        -- glass speed below which sgn(v) is linear in v
  constant seal_friction_position0   : displacement := 0.0;           -- glass position at t = 0

  -- top_frame_seal (vhdl/door/top_frame_seal.vhd)
  constant top_frame_seal_position        : displacement := 0.37;                    -- glass position where the sealing begins
  constant top_frame_seal_lengths         : real_vector  := (0.010, 0.010, 0.010);   -- [m] lengths of the three intrusion ranges
  constant top_frame_seal_frictions       : real_vector  := (5.0, 10.0, 15.0);       -- [N] friction force in each range
  constant top_frame_seal_stiffnesses     : real_vector  := (1.0e3, 3.0e3, 10.0e3);  -- [N/m] sealing stiffness in each range
  constant top_frame_seal_frame_stiffness : stiffness    := 1.0e6;                   -- stiffness of the metal door frame
  constant top_frame_seal_v_threshold     : velocity     := 1.0e-3;                  -- speed below which sgn(v) is linear
  constant top_frame_seal_position0       : displacement := 0.0;                     -- glass position at t = 0

  -- dcpm_motor (vhdl/drive/dcpm_motor.vhd)
  constant dcpm_motor_ke              : real             := 21.7e-3;  -- [V*s/rad] back-EMF constant k_e
  constant dcpm_motor_kt              : real             := 15.0e-3;  -- [N*m/A] torque constant k_t
  constant dcpm_motor_ra              : resistance       := 0.57;     -- effective armature resistance R_a (winding, brushes, commutator)
  constant dcpm_motor_laa             : inductance       := 0.09e-3;  -- effective armature inductance L_a
  constant dcpm_motor_j               : moment_inertia   := 9.85e-6;  -- effective rotor inertia J_a
  constant dcpm_motor_visc            : angular_damping  := 0.0;      -- viscous friction coefficient Visc
  constant dcpm_motor_mc              : torque           := 0.0;      -- Coulomb friction torque M_c (bearings, brushes)
  constant dcpm_motor_omega_threshold : angular_velocity := 1.0e-3;   -- speed below which the Coulomb torque is linear in omega
  constant dcpm_motor_ia0             : current          := 0.0;      -- armature current at the DC operating point (real'low: free)
  constant dcpm_motor_angle0          : angle            := 0.0;      -- shaft angle at t = 0
  constant dcpm_motor_omega0          : angular_velocity := 0.0;      -- shaft speed at the DC operating point (real'low: free)

  -- drive (vhdl/drive/drive.vhd)
  constant drive_m_gc : torque := 0.0;  -- Coulomb friction M_gc of gear and housing (Eq. 4.31), acting at the gear wheel

  -- rotational_friction (vhdl/drive/rotational_friction.vhd)
  constant rotational_friction_m_c             : torque           := 0.0;     -- Coulomb friction torque magnitude
  constant rotational_friction_omega_threshold : angular_velocity := 1.0e-3;  -- speed below which the friction torque is linear in omega

  -- rubber_damper (vhdl/drive/rubber_damper.vhd)
  constant rubber_damper_angles    : real_vector := (0.0, 0.0349, 0.0698, 0.1047, 0.1396, 0.1745);  -- [rad] deformation breakpoints of the stiffness table
  constant rubber_damper_stiffness : real_vector := (57.3, 51.6, 48.7, 47.7, 51.6, 68.8);           -- [N*m/rad] stiffness c at each breakpoint

  -- worm_gear (vhdl/drive/worm_gear.vhd)
  constant worm_gear_ratio           : real             := 73.0;            -- [1] gear ratio i = Z2/Z1 (worm revolutions per gear-wheel revolution)
  constant worm_gear_eta             : real             := 0.45;            -- [1] forward power efficiency eta = P_gear/P_worm in driving mode
  constant worm_gear_omega_threshold : angular_velocity := 1.0e-3;          -- gear-wheel speed below which the friction sign is linear
  constant worm_gear_r_worm          : displacement     := 3.805745782e-3;  -- pitch radius r_w of the worm
  constant worm_gear_r_gear          : displacement     := 29.2e-3;         -- pitch radius r_g of the gear wheel
  constant worm_gear_lead_angle      : angle            := 0.1047197551;    -- lead angle phi_l at the pitch circle (6 deg)
  constant worm_gear_press_angle     : angle            := 0.2007128640;    -- press angle phi_p (11.5 deg; three_d only)
  constant worm_gear_mu_contact      : real             := 0.1051042353;    -- [1] Coulomb friction coefficient mu_c at the contacting face
  constant worm_gear_mu_bearing      : real             := 0.0;             -- [1] Coulomb friction coefficient of the worm and gear bearings
  constant worm_gear_r_bearing_worm  : displacement     := 2.5e-3;          -- friction radius of the worm-shaft bearing
  constant worm_gear_r_bearing_gear  : displacement     := 4.0e-3;          -- friction radius of the gear-shaft bearing

  -- h_bridge (vhdl/electronics/h_bridge.vhd)
  constant h_bridge_r_ds_on   : resistance := 5.0e-3;  -- on-resistance of one MOSFET at its junction temperature (automotive 40 V trench MOSFET, 20 degC)
  constant h_bridge_v_f       : voltage    := 0.8;     -- body diode forward voltage
  constant h_bridge_r_f       : resistance := 5.0e-3;  -- body diode slope resistance
  constant h_bridge_dead_time : real       := 5.0e-7;  -- [s] both MOSFETs of a leg off at each switching
  constant h_bridge_f_pwm     : real       := 2.0e4;   -- [Hz] PWM frequency (above hearing: 20 kHz)
  constant h_bridge_i_band    : current    := 0.05;    -- current below which a body diode is smoothed off

  -- ecu_sense (vhdl/electronics/ecu_sense.vhd)
  constant ecu_sense_r_shunt  : resistance := 1.0e-3;  -- shunt resistance
  constant ecu_sense_gain     : real       := 100.0;   -- [V/V] amplifier gain
  constant ecu_sense_v_adc    : voltage    := 5.0;     -- ADC reference (full scale)

  -- ecu_hardware (vhdl/electronics/ecu_hardware.vhd)
  constant ecu_hardware_r_contact : resistance := 0.0;  -- resistance of a closed relay contact (0 = ideal)

  -- hall_sensor (vhdl/electronics/hall_sensor.vhd)
  constant hall_sensor_pole_shares : real_vector := (0.25, 0.25, 0.25, 0.25);  -- [1] shares of the 4 poles in one revolution
  constant hall_sensor_pole_offset : angle       := -1.1780972450961724;       -- armature angle where pole 1 begins (-3*pi/8)
  constant hall_sensor_phase_shift : angle       := 0.7853981633974483;        -- angle by which sensor B lags A (pi/4)

  -- antipinch_gauge (vhdl/equipment/antipinch_gauge.vhd)
  constant antipinch_gauge_stiffness      : stiffness    := 10.0e3;  -- spring rate of the gauge
  constant antipinch_gauge_pinch_position : displacement := 0.36;    -- glass position at which the rod touches the frame
  constant antipinch_gauge_pinch_angle    : angle        := 0.0;     -- angle between the rod (pinch force) and the glass motion
  constant antipinch_gauge_position0      : displacement := 0.0;     -- glass position at t = 0

  -- battery (vhdl/equipment/battery.vhd)
  constant battery_u          : voltage    := 13.0;  -- open-circuit voltage (thesis: nominal 13 V)
  constant battery_r_internal : resistance := 0.0;   -- internal resistance of battery and wiring

  -- dc_supply (vhdl/equipment/dc_supply.vhd)
  constant dc_supply_u          : voltage    := 13.0;  -- open-circuit source voltage v(p) - v(n)
  constant dc_supply_r_internal : resistance := 0.0;   -- internal series resistance (0 = ideal voltage source)

  -- door_disturbance (vhdl/equipment/door_disturbance.vhd)
  constant door_disturbance_glass_mass  : mass         := 2.55;    -- mass of the glass the door carries
  constant door_disturbance_accel       : acceleration := 0.0;     -- amplitude of the door's vertical acceleration
  constant door_disturbance_frequency   : real         := 12.0;    -- [Hz] frequency of that acceleration
  constant door_disturbance_band_high   : real         := 0.0;     -- [Hz] a random road: the band's upper edge
  constant door_disturbance_lines       : natural      := 0;       -- [1] a random road: its sinusoids (0: one sinusoid)
  constant door_disturbance_seed        : natural      := 1;       -- [1] a random road: draws its frequencies and phases
  constant door_disturbance_friction    : force        := 0.0;     -- extra seal friction against the glass velocity (< 0: less)
  constant door_disturbance_t_on        : real         := 0.0;     -- [s] the disturbance starts
  constant door_disturbance_v_threshold : velocity     := 1.0e-3;  -- speed below which sgn(v) is linear

  -- lab_supply (vhdl/equipment/lab_supply.vhd)
  constant lab_supply_u_nominal  : voltage    := 13.0;  -- open-circuit voltage at offset 0 (thesis: nominal 13 V)
  constant lab_supply_r_internal : resistance := 0.0;   -- internal resistance of source and wiring

  -- pwl_supply (vhdl/equipment/pwl_supply.vhd)
  constant pwl_supply_times  : real_vector := (0.0, 1.0);  -- [s] breakpoints of the voltage table, strictly increasing
  constant pwl_supply_values : real_vector := (0.0, 0.0);  -- [V] source voltage v(p) - v(n) at each breakpoint

  -- torque_ramp (vhdl/equipment/torque_ramp.vhd)
  constant torque_ramp_torque_end : torque := 0.5;  -- brake torque magnitude at the end of the ramp
  constant torque_ramp_ramp_time  : real   := 3.0;  -- [s] duration of the ramp from 0 to torque_end
  constant torque_ramp_t_start    : real   := 0.0;  -- [s] time at which the ramp starts (torque 0 before)
  constant torque_ramp_direction  : real   := 1.0;  -- [1] sign of the braked rotation: +1.0 or -1.0

  -- bowden (vhdl/mechanism/bowden.vhd)
  constant bowden_mu          : real     := 0.08;    -- [1] friction coefficient between cable and inner tube (or fixed pulley)
  constant bowden_alpha       : angle    := 1.5708;  -- wrap angle alpha of the cable
  constant bowden_v_threshold : velocity := 1.0e-3;  -- cable speed below which sgn(V) is linear in V

  -- cable_drum (vhdl/mechanism/cable_drum.vhd)
  constant cable_drum_r_cd            : displacement     := 0.022;   -- wrapping radius of the cable r_cd (Tab. 4.9)
  constant cable_drum_r_gs            : displacement     := 0.004;   -- radius of the gear shaft r_gs (Tab. 4.9)
  constant cable_drum_alpha_c         : angle            := 2.618;   -- angle alpha_c of Eq. 4.36e (Tab. 4.9, see header)
  constant cable_drum_mu_gs           : real             := 0.10;    -- [1] Coulomb friction coefficient gear/shaft mu_gs (Tab. 4.9)
  constant cable_drum_j_cd            : moment_inertia   := 1.0e-5;  -- inertia of drum and drive output (see header)
  constant cable_drum_omega_threshold : angular_velocity := 1.0e-3;  -- speed below which the friction torque is linear in omega

  -- compressing_spring (vhdl/mechanism/compressing_spring.vhd)
  constant compressing_spring_k            : stiffness    := 3000.0;  -- spring stiffness in the normal working range
  constant compressing_spring_travel_block : displacement := 0.025;   -- compression at which the spring goes into block
  constant compressing_spring_k_block      : stiffness    := 27.6e3;  -- block stiffness = system stiffness of the mechanism
  constant compressing_spring_spacer       : displacement := 0.015;   -- spacer length: compression at zero cable elongation
  constant compressing_spring_state        : real         := 0.0;     -- [1] tension distribution at t = 0 (-1 .. 1, see header)

  -- lever (vhdl/mechanism/lever.vhd)
  constant lever_ratio_a : real := 0.4;  -- [1] share of the glass load on pin a (slider A); pin b carries 1 - ratio_a

  -- pulley (vhdl/mechanism/pulley.vhd)
  constant pulley_mu          : real         := 0.069;   -- [1] friction coefficient between pulley and its shaft
  constant pulley_r_in        : displacement := 0.006;   -- radius of the pulley shaft r_in
  constant pulley_r_out       : displacement := 0.020;   -- wrapping radius of the cable over the pulley r_out
  constant pulley_alpha       : angle        := 2.8274;  -- wrap angle alpha of the cable (162 deg)
  constant pulley_v_threshold : velocity     := 1.0e-3;  -- cable speed below which sgn(V) is linear in V

  -- rail_stop (vhdl/mechanism/rail_stop.vhd)
  constant rail_stop_position0    : displacement := 0.0;        -- glass position at t = 0
  constant rail_stop_position_min : displacement := 0.0;        -- lower end of the travel (window fully open)
  constant rail_stop_position_max : displacement := real'high;  -- upper end of the travel
  constant rail_stop_stiffness    : stiffness    := 1.0e6;      -- stop stiffness

  -- rail_wr (vhdl/mechanism/rail_wr.vhd)
  constant rail_wr_drum_diameter   : displacement := 0.044;                             -- cable drum (wrapping) diameter
  constant rail_wr_glass_position0 : displacement := 0.0;                               -- glass position at t = 0
  constant rail_wr_tension_state   : real         := 0.0;                               -- [1] tension distribution at t = 0
  constant rail_wr_bowden_alpha    : real_vector  := (1.5708, 1.5708, 1.5708);          -- [rad] bowden wrap angles, loop order
  constant rail_wr_pulley_alpha    : real_vector  := (2.8274, 2.8274, 2.8274, 2.8274);  -- [rad] pulley wrap angles, loop order

  -- rotational_spring (vhdl/mechanism/rotational_spring.vhd)
  constant rotational_spring_stiffness : angular_stiffness := 1.0;  -- torsional stiffness c

  -- slider (vhdl/mechanism/slider.vhd)
  constant slider_f_0             : force    := 5.0;     -- friction offset f_0 of the slider type (Fig. 4.56 fit)
  constant slider_mu_load         : real     := 0.10;    -- [1] friction slope over the slider's load (Fig. 4.56 fit)
  constant slider_reduction_angle : angle    := 0.0;     -- rail reduction angle beta against the glass's direction of motion
  constant slider_v_threshold     : velocity := 1.0e-3;  -- slider speed below which sgn(v) is linear in v

  -- window_regulator (vhdl/systems/window_regulator.vhd)
  constant window_regulator_drum_diameter   : displacement := 0.044;  -- cable drum diameter
  constant window_regulator_glass_position0 : displacement := 0.0;    -- glass position at t = 0 (0 = fully open)
  constant window_regulator_tension_state   : real         := 0.0;    -- [1] tension distribution of the cable loop at t = 0
end package wr_params;
