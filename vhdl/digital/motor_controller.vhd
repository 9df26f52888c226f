library IEEE;
use IEEE.STD_LOGIC_1164.all;
use IEEE.NUMERIC_STD.all;
use work.wr_digital_params.all;

-- motor_controller: the motor-control software of the semiconductor ECU (this project's design; the thesis's ECU
-- is the relay one, 4.3.3.1): between the window-lift software (ecu_software: position, normalization, anti-pinch,
-- reversal) and the H-bridge (h_bridge). ecu_software asks for a run up or down on its relay outputs, as it asks
-- the relay pair; this unit turns the request into a regulated motor speed. Digital VHDL-2008, run by GHDL.
--
-- Timing: the control task runs at every Hall-A edge (input capture with the 1 us timer, as ecu_software: the speed
-- is new there), at a change of the request, and, while the motor is driven or braked, idle_ms after the last task
-- when neither came (a start from rest, a stall); it reads the ADC's last conversions (ecu_sense). The bridge takes a
-- new duty, mode or direction at the end of the analog solver's step in which it changed (at most max_step, 1 ms,
-- later; typically some 10 us; the ports are `wrsim_lazy`, docs/vhdl-ams-subset.md "Mixed signal"): as the PWM
-- unit's shadow registers load at its next period. Reported at once, each change would cut the analog step back,
-- and the other digital units lose input events: measured, ecu_software lost 72 of 4090 Hall edges in one compliance
-- run with a 1 ms task on a free timer, and with a task at every Hall edge the switch missed the position for 150 ms.
--
-- Speed: from the captured Hall-A edges, 4 per armature revolution: n = 60e6*k/(4*(t_last - t_(last-k))) [rpm]
-- over the last 2 <= k <= 4 edge intervals (0 before the run's third edge: a single interval of an armature that
-- starts from rest, or rocks on its damper, is no speed); while no edge comes, n is at most the speed the time
-- since the last edge allows, 60e6/(4*(t - t_last)); none for speed_timeout_ms: 0.
--
-- Profile of a run up (the set speed n_ref starts from 0 at the run's start and follows the target at most
-- ramp_mm_s2, so every start is soft, however long the controller was idle before it):
--   close_mm_s from the start; once normalized, pinch_mm_s within pinch_zone_mm below the top, and stop_mm_s within
--   soft_stop_mm (the approach to the top block); at most start_mm_s for the first start_ms of every run up (a start
--   from rest: the anti-pinch algorithm has no load history yet, docs/anti-pinch.md "Start-up"; 0: none). A run
--   down: open_mm_s. Speeds in mm/s of glass, converted with
--   edges_per_m (4 edges per revolution): n [rpm] = v*edges_per_m*60/4/1000.
-- Control law (PI on the speed, supply feed-forward; u is the mean motor voltage, the duty u/U):
--   u = n_ref/rpm_per_volt + kp*(n_ref - n) + x          x += ki*(n_ref - n)*dt
--   u limited to 0 .. U (the duty to 0 .. 1) and to n/rpm_per_volt + r_motor*i_limit (the current limit: the
--   back-EMF and the armature's drop at i_limit), and below that as the measured current exceeds i_limit:
--   u -= r_motor*(i - i_limit). Anti-windup: x is held while u is limited and would grow further that way.
--   With the supply measured and fed forward the speed does not depend on the supply nor on the temperature while
--   the duty allows; at a low supply the duty reaches 1 and the drive runs as on the relays.
-- Braking: a request for the other direction, or for a stop, while the armature turns: both low sides on (active
-- brake) until the speed falls below brake_rpm or brake_max_ms have passed; then the new run starts from rest, or
-- the bridge stays braked (a stop: the motor short-circuited, as the relay ECU's stop).
-- Effort: the mean voltage the motor is driven with, duty*U, in 0.1 V (8 bits: 0 .. 25.5 V), to ecu_software's
-- supply input: its anti-pinch algorithms model the motor driven by a voltage (docs/anti-pinch.md), which is
-- the controller's effort here, not the battery's voltage; 0 while braking.
--
-- Inputs: hall_a, hall_b; supply_code [0.1 V] and current_code [ADC steps] (ecu_sense); run_up, run_down
-- (ecu_software's relay outputs); position [edges below the top] and normalized (ecu_software).
-- Outputs: duty [1/1023], mode ("00" off, "01" drive, "10" freewheel, "11" brake), dir ('1' up), effort [0.1 V].
-- Generics: integer, units in the comments; ranges in the asserts.
-- Limits: no thermal protection of the bridge, no supply under-/overvoltage cut-off; the ADC's zero current at
-- code 512 (ecu_sense); the speed measurement assumes equal pole shares within a revolution's average; the 1 us
-- timer is a VHDL integer: at most 2**31 - 1 us (35 min) of simulated time.
entity motor_controller is
  generic (
    idle_ms          : positive := motor_controller_idle_ms;           -- [ms] a task this long after the last (running)
    edges_per_m      : positive := motor_controller_edges_per_m;       -- [1/m] Hall-A edges per metre of glass
    rpm_per_volt     : positive := motor_controller_rpm_per_volt;      -- [rpm/V] no-load armature speed per volt
    close_mm_s       : positive := motor_controller_close_mm_s;        -- [mm/s] closing speed
    pinch_mm_s       : positive := motor_controller_pinch_mm_s;        -- [mm/s] closing speed in the pinch zone
    pinch_zone_mm    : natural  := motor_controller_pinch_zone_mm;     -- [mm] pinch zone below the top
    stop_mm_s        : positive := motor_controller_stop_mm_s;         -- [mm/s] closing speed before the top block
    soft_stop_mm     : natural  := motor_controller_soft_stop_mm;      -- [mm] ... within this distance of the top
    open_mm_s        : positive := motor_controller_open_mm_s;         -- [mm/s] opening speed
    start_mm_s       : positive := motor_controller_start_mm_s;        -- [mm/s] closing speed at most, right after
    start_ms         : natural  := motor_controller_start_ms;          -- [ms] ... a start, for this long
    ramp_mm_s2       : positive := motor_controller_ramp_mm_s2;        -- [mm/s**2] largest change of the set speed
    kp_uv_per_rpm    : natural  := motor_controller_kp_uv_per_rpm;     -- [uV/rpm] proportional gain
    ki_uv_per_rpm_s  : natural  := motor_controller_ki_uv_per_rpm_s;   -- [uV/(rpm*s)] integral gain
    i_limit_ma       : positive := motor_controller_i_limit_ma;        -- [mA] motor current limit
    r_motor_mohm     : positive := motor_controller_r_motor_mohm;      -- [mOhm] armature resistance (current limit)
    current_lsb_ua   : positive := motor_controller_current_lsb_ua;    -- [uA] current per ADC step (ecu_sense)
    brake_rpm        : natural  := motor_controller_brake_rpm;         -- [rpm] braking ends below this speed
    brake_max_ms     : positive := motor_controller_brake_max_ms;      -- [ms] longest braking
    speed_timeout_ms : positive := motor_controller_speed_timeout_ms); -- [ms] no edge this long: speed 0
  port (
    hall_a, hall_b   : in std_logic;                       -- Hall signals (hall_sensor)
    supply_code      : in std_logic_vector(7 downto 0);    -- [0.1 V] supply (ecu_sense)
    current_code     : in std_logic_vector(9 downto 0);    -- [ADC steps] motor current (ecu_sense)
    run_up, run_down : in std_logic;                       -- requests (ecu_software's relay outputs)
    position         : in std_logic_vector(31 downto 0);   -- [edges] below the top (ecu_software)
    normalized       : in std_logic;                       -- '1' once the top is known (ecu_software)
    duty             : out std_logic_vector(9 downto 0);   -- [1/1023] duty of the switching leg (h_bridge)
    mode             : out std_logic_vector(1 downto 0);   -- h_bridge mode
    dir              : out std_logic;                      -- '1' up (h_bridge)
    effort           : out std_logic_vector(7 downto 0));  -- [0.1 V] mean motor voltage (ecu_software)
  -- The bridge's inputs change in reaction to this unit's inputs (a Hall edge, a request) or at an idle task; wrsim
  -- reports them at the end of the analog step that holds the change (a user attribute other tools ignore).
  attribute wrsim_lazy : boolean;
  attribute wrsim_lazy of duty, mode, dir : signal is true;
end entity motor_controller;

architecture behavioral of motor_controller is
  type state_t is (stopped, braking, running);
  type times_t is array (0 to 4) of natural;
  constant rpm_per_mm_s : real := real(edges_per_m) * 60.0 / 4.0 / 1000.0;  -- [rpm/(mm/s)]
begin
  assert idle_ms <= 100 report "motor_controller: idle_ms must be <= 100" severity failure;
  assert stop_mm_s <= close_mm_s and pinch_mm_s <= close_mm_s and start_mm_s <= close_mm_s
    report "motor_controller: stop_mm_s, pinch_mm_s and start_mm_s must not exceed close_mm_s" severity failure;
  assert start_ms <= 10_000 report "motor_controller: start_ms must be <= 10000" severity failure;
  assert soft_stop_mm <= 1000 and pinch_zone_mm <= 1000
    report "motor_controller: soft_stop_mm and pinch_zone_mm must be <= 1000" severity failure;
  assert i_limit_ma <= 50_000 report "motor_controller: i_limit_ma must be <= 50000" severity failure;

  control: process
    variable t_us      : natural := 0;          -- [us] the timer at this activation
    variable t_task    : natural := 0;          -- [us] the last control task
    variable task      : boolean := true;       -- the control task runs in this activation (also at time 0)
    variable req_old   : std_logic_vector(1 downto 0) := "UU";
    variable a_old     : std_logic := 'U';
    variable edges     : times_t := (others => 0);  -- [us] the last Hall-A edges of the run, newest first
    variable n_edges   : natural := 0;          -- edges of the run captured (at most 5 used)
    variable state     : state_t := stopped;
    variable up        : boolean := true;       -- direction of the run (or of the one braking ends in)
    variable want      : integer := 0;          -- request: 1 up, -1 down, 0 stop
    variable going     : integer := 0;          -- the request the present run or braking serves
    variable brake_t0  : natural := 0;          -- [us] start of braking
    variable run_t0    : natural := 0;          -- [us] start of the present run
    variable n_ref     : real := 0.0;           -- [rpm] set speed
    variable n_meas    : real := 0.0;           -- [rpm] measured speed
    variable x_int     : real := 0.0;           -- [V] integral part
    variable u_cmd     : real := 0.0;           -- [V] mean motor voltage
    variable u_bat     : real := 0.0;           -- [V] supply
    variable i_meas    : real := 0.0;           -- [A] motor current (positive in the run's direction)
    variable target    : real;
    variable dt        : real;
    variable err       : real;
    variable u_lim     : real;
    variable limited   : boolean;
    variable pos       : integer;
    variable d_code    : integer := 0;

    -- [rpm] the speed the captured edges give at time t_us (header).
    impure function speed return real is
      variable k : natural;
      variable n : real;
    begin
      if n_edges < 3 or t_us - edges(0) >= speed_timeout_ms * 1000 then
        return 0.0;
      end if;
      k := n_edges - 1;
      if k > 4 then
        k := 4;
      end if;
      n := 60.0e6 * real(k) / (4.0 * real(edges(0) - edges(k) + 1));
      if t_us > edges(0) and 60.0e6 / (4.0 * real(t_us - edges(0))) < n then
        n := 60.0e6 / (4.0 * real(t_us - edges(0)));
      end if;
      return n;
    end function speed;
  begin
    loop
      t_us := now / 1 us;

      -- Input capture: a Hall-A edge.
      if (hall_a = '0' or hall_a = '1') and (a_old = '0' or a_old = '1') and hall_a /= a_old then
        edges := t_us & edges(0 to 3);
        n_edges := n_edges + 1;
        task := true;
      end if;
      a_old := hall_a;
      if run_up & run_down /= req_old or (state /= stopped and t_us - t_task >= idle_ms * 1000) then
        req_old := run_up & run_down;
        task := true;
      end if;

      -- The control task.
      if task then
        task := false;
        dt := real(t_us - t_task) * 1.0e-6;
        t_task := t_us;
        -- The request.
        if run_up = '1' and run_down /= '1' then
          want := 1;
        elsif run_down = '1' and run_up /= '1' then
          want := -1;
        else
          want := 0;
        end if;
        if want /= going then     -- a new request: brake first if the armature turns
          going := want;
          n_meas := speed;
          if n_meas > real(brake_rpm) then
            state := braking;
            brake_t0 := t_us;
          elsif want = 0 then
            state := stopped;
          else
            state := running;
            up := want = 1;
            n_ref := 0.0;
            x_int := 0.0;
            n_edges := 0;
            run_t0 := t_us;
            dt := 0.0;            -- the run starts now: the time since the last task is not the run's
          end if;
          if want /= 0 then
            up := want = 1;
          end if;
        end if;

        n_meas := speed;
        if not is_x(supply_code) then
          u_bat := 0.1 * real(to_integer(unsigned(supply_code)));
        end if;
        if not is_x(current_code) then
          i_meas := (real(to_integer(unsigned(current_code))) - 511.5) * real(current_lsb_ua) * 1.0e-6;
          if not up then
            i_meas := -i_meas;
          end if;
        end if;
        if state = braking and (n_meas <= real(brake_rpm) or t_us - brake_t0 >= brake_max_ms * 1000) then
          if going = 0 then
            state := stopped;
          else
            state := running;
            n_ref := 0.0;
            x_int := 0.0;
            n_edges := 0;
            run_t0 := t_us;
            n_meas := 0.0;
            dt := 0.0;
          end if;
        end if;
        if state = running then
          pos := to_integer(signed(position));
          if not up then
            target := real(open_mm_s);
          elsif normalized = '1' and pos * 1000 <= soft_stop_mm * edges_per_m then
            target := real(stop_mm_s);
          elsif normalized = '1' and pos * 1000 <= pinch_zone_mm * edges_per_m then
            target := real(pinch_mm_s);
          else
            target := real(close_mm_s);
          end if;
          if up and t_us - run_t0 < start_ms * 1000 and target > real(start_mm_s) then
            target := real(start_mm_s);
          end if;
          target := target * rpm_per_mm_s;
          if n_ref < target then
            n_ref := n_ref + real(ramp_mm_s2) * rpm_per_mm_s * dt;
            if n_ref > target then
              n_ref := target;
            end if;
          elsif n_ref > target then
            n_ref := n_ref - real(ramp_mm_s2) * rpm_per_mm_s * dt;
            if n_ref < target then
              n_ref := target;
            end if;
          end if;
          err := n_ref - n_meas;
          u_cmd := n_ref / real(rpm_per_volt) + real(kp_uv_per_rpm) * 1.0e-6 * err + x_int;
          u_lim := n_meas / real(rpm_per_volt) + real(r_motor_mohm) * 1.0e-3 * real(i_limit_ma) * 1.0e-3;
          if i_meas > real(i_limit_ma) * 1.0e-3 then
            u_lim := u_lim - real(r_motor_mohm) * 1.0e-3 * (i_meas - real(i_limit_ma) * 1.0e-3);
          end if;
          if u_bat < u_lim then
            u_lim := u_bat;
          end if;
          limited := false;
          if u_cmd > u_lim then
            u_cmd := u_lim;
            limited := err > 0.0;
          end if;
          if u_cmd < 0.0 then
            u_cmd := 0.0;
            limited := err < 0.0;
          end if;
          if not limited then
            x_int := x_int + real(ki_uv_per_rpm_s) * 1.0e-6 * err * dt;
          end if;
        end if;

        -- Outputs.
        if state = running and u_bat > 0.0 then
          d_code := integer(u_cmd / u_bat * 1023.0);
          if d_code > 1023 then
            d_code := 1023;
          end if;
          mode <= "01";
          effort <= std_logic_vector(to_unsigned(integer(real(d_code) / 1023.0 * u_bat * 10.0), 8));
        elsif state = running then
          d_code := 0;
          mode <= "01";
          effort <= (others => '0');
        else
          d_code := 0;
          mode <= "11";           -- braking, or stopped: the motor short-circuited
          effort <= (others => '0');
        end if;
        duty <= std_logic_vector(to_unsigned(d_code, 10));
        if up then
          dir <= '1';
        else
          dir <= '0';
        end if;

      end if;

      -- Sleep until a Hall-A edge, a new request or, while the motor is driven or braked, the idle task.
      if state = stopped then
        wait on hall_a, run_up, run_down;
      else
        wait on hall_a, run_up, run_down for (t_task + idle_ms * 1000) * 1 us - now;
      end if;
    end loop;
  end process control;
end architecture behavioral;
