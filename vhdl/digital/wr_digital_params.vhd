-- wr_digital_params: the default value of every generic of the digital models (the ECU software and the
-- switch, plain VHDL that GHDL co-simulates), one constant per generic, named <entity>_<generic>; each
-- entity's generic list reads its defaults from here (`threshold_rpm : positive := ecu_software_threshold_rpm`).
-- A parameter set (params/*.txt) replaces these values. For another simulator, `wrsim export --params SET`
-- writes this package with the set's values: analyse that file into library WORK instead of this one,
-- before the digital models (README, "Import into Saber or SystemVision").
-- Keep one constant per line, `constant <entity>_<generic> : <type> := <value>;`: the export replaces lines.
package wr_digital_params is
  -- ecu_software (vhdl/digital/ecu_software.vhd)
  constant ecu_software_stall_time_ms    : positive := 500;   -- [ms] no Hall-A edge this long with a relay on = stall (5.2.1)
  constant ecu_software_edges_per_m      : positive := 2112;  -- [1/m] Hall-A edges per metre of glass travel (2.112 per mm)
  constant ecu_software_no_pinch_zone_mm : natural  := 4;     -- [mm] anti-pinch off this close below the top
  constant ecu_software_rpm_per_volt     : positive := 449;   -- [rpm/V] no-load armature speed per volt of supply
  constant ecu_software_threshold_rpm    : positive := 250;   -- [rpm] speed deficit above the reference that is a pinch
  constant ecu_software_startup_rpm      : natural  := 400;   -- [rpm] extra threshold at a start, falling linearly to 0
  constant ecu_software_startup_ms       : natural  := 1000;  -- [ms] duration of that fall (0 = no extra threshold)
  constant ecu_software_blank_edges      : natural  := 12;    -- [edges] no detection and no learning after a start
  constant ecu_software_edges_per_bin    : positive := 8;     -- [edges] length of one bin of the reference
  constant ecu_software_reference_bins   : positive := 128;   -- [1] number of bins (from the top down)
  constant ecu_software_learn_shift      : natural  := 2;     -- [1] a later run up moves the reference by 1/2**learn_shift
  constant ecu_software_reverse_mm       : positive := 100;   -- [mm] travel down after a pinch
  constant ecu_software_max_run_edges    : positive := 2048;  -- [edges] longest run up that is learned
  constant ecu_software_algorithm        : natural  := 0;     -- [1] anti-pinch: 0 the package's VHDL, 1 its C twin antipinch.c, 2-6 see ecu_software
  constant ecu_software_supply_tau_ms    : positive := 20;    -- [ms] algorithms 2-6: the drive's mechanical time constant J*ra/(ke*kt)
  constant ecu_software_mode_ms          : positive := 67;    -- [ms] algorithms 5, 6: period of the glass swinging on its cable springs
  constant ecu_software_rpm_per_newton   : positive := 13;    -- [rpm/N] speed deficit per newton at the glass: scales `estimate`
  constant ecu_software_rpm_per_amp      : positive := 418;   -- [rpm/A] algorithm 7: speed deficit per ampere (ra/ke)
  constant ecu_software_current_lsb_ua   : positive := 48828; -- [uA] motor current per step of current_code
  constant ecu_software_learned_file     : string   := "";    -- [-] warm start: the learned state to power up with ("": cold start)
  constant ecu_software_start_position   : integer  := 0;     -- [edges] warm start: the position at power-up
  constant ecu_software_learned_out      : string   := "";    -- [-] file the learned state is written to ("": none)
  constant ecu_software_reverse_on_pinch : boolean  := true;  -- [-] false: a detection is held off (recording a closing)
  constant ecu_software_record_out       : string   := "";    -- [-] file the ECU's inputs are recorded to ("": none)

  -- motor_controller (vhdl/digital/motor_controller.vhd)
  constant motor_controller_idle_ms          : positive := 5;      -- [ms] a task this long after the last (running)
  constant motor_controller_edges_per_m      : positive := 2112;   -- [1/m] Hall-A edges per metre of glass
  constant motor_controller_rpm_per_volt     : positive := 480;    -- [rpm/V] no-load armature speed per volt
  constant motor_controller_close_mm_s       : positive := 125;    -- [mm/s] closing speed
  constant motor_controller_pinch_mm_s       : positive := 125;    -- [mm/s] closing speed in the pinch zone
  constant motor_controller_pinch_zone_mm    : natural  := 200;    -- [mm] pinch zone below the top
  constant motor_controller_stop_mm_s        : positive := 60;     -- [mm/s] closing speed before the top block
  constant motor_controller_soft_stop_mm     : natural  := 10;     -- [mm] ... within this distance of the top
  constant motor_controller_open_mm_s        : positive := 150;    -- [mm/s] opening speed
  constant motor_controller_start_mm_s       : positive := 125;    -- [mm/s] closing speed at most, right after a start
  constant motor_controller_start_ms         : natural  := 0;      -- [ms] ... for this long (0: none)
  constant motor_controller_ramp_mm_s2       : positive := 2000;   -- [mm/s**2] largest change of the set speed
  constant motor_controller_kp_uv_per_rpm    : natural  := 900;    -- [uV/rpm] proportional gain
  constant motor_controller_ki_uv_per_rpm_s  : natural  := 40000;  -- [uV/(rpm*s)] integral gain
  constant motor_controller_i_limit_ma       : positive := 14000;  -- [mA] motor current limit
  constant motor_controller_r_motor_mohm     : positive := 870;    -- [mOhm] armature resistance (current limit)
  constant motor_controller_current_lsb_ua   : positive := 48828;  -- [uA] current per ADC step (ecu_sense)
  constant motor_controller_brake_rpm        : natural  := 300;    -- [rpm] braking ends below this speed
  constant motor_controller_brake_max_ms     : positive := 100;    -- [ms] longest braking
  constant motor_controller_speed_timeout_ms : positive := 100;    -- [ms] no edge this long: speed 0

  -- switch (vhdl/digital/switch.vhd)
  constant switch_sequence_file : string   := "switch_sequence.txt";  -- [-] path of the sequence file
  constant switch_edges_per_m   : positive := 2112;                   -- [1/m] Hall-A edges per metre of glass travel
  constant switch_release_ms    : natural  := 100;                    -- [ms] command "00" after each P unit
end package wr_digital_params;
