library IEEE;
use IEEE.STD_LOGIC_1164.all;
use IEEE.NUMERIC_STD.all;
use work.antipinch.all;
use work.wr_digital_params.all;
use std.textio.all;

-- ecu_software: the software of the window-regulator ECU (thesis 4.3.3.1, Fig. 4.76; 5.1 a; normalization
-- 5.2.1; anti-pinch 5.3.2). Digital VHDL-2008, run by GHDL (mixed-signal contract,
-- docs/vhdl-ams-subset.md); the relays and the supply digitisation are ecu_hardware, the Hall signals come
-- from hall_sensor. The thesis's anti-trap module is Brose know-how (a DLL) and not published: the
-- anti-pinch algorithm here is this project's own design, described in docs/anti-pinch.md.
--
-- Timing, as on the ECU's microcontroller: no polling clock; the software runs on its interrupts. Time is
-- a free-running 1 us timer (natural: it overflows after 2**31 us = 35.8 min, 5.2.1: "the maximal time
-- which the register can represent is fixed"). (1) Input capture: every Hall-A edge latches the timer and
-- runs the edge handler at once (count, speed, learning, detection); the revolution time of the speed
-- measurement is the difference of two captured times. (2) A change of the switch command is handled when
-- it arrives. (3) A compare timer, set to the last Hall-A edge of the run + stall_time_ms, runs the stall
-- handler. The software therefore wakes only when something happens, and every output changes at the
-- instant of its cause (in a mixed-signal run no digital clock forces the analog solver's step).
--
-- Position (electronic position, 4.3.2 / 5.2.1): a quadrature counter of the Hall-A edges, 4 per armature
-- revolution. At an edge of A the direction follows from B: new A /= B = positive rotation (lifting, B lags
-- A, hall_sensor), new A = B = negative rotation. Lifting counts down, lowering counts up ("the change of
-- position counter and physical position are opposite", Fig. 5.3). Counted whether or not a relay is on
-- (coasting counts too). edges_per_m converts to glass travel: 4 edges per revolution * gear ratio 73 /
-- (pi * drum diameter 44 mm) = 2112 edges per metre (2.11 per mm); the cable springs make the real
-- travel per edge depend on the load by a few per cent.
--
-- Normalization (5.2.1): at power-on the position is 0 and normalized = '0'. A run up that ends in a stall
-- (no Hall-A edge for stall_time_ms, 500 ms) sets the position to 0 and normalized = '1'; from then on
-- the position is the distance below the top in edges. The run up is the learning run of the anti-pinch
-- reference; anti-pinch is off until the ECU is normalized.
--
-- Warm start (docs/anti-pinch.md, "Warm start"): with learned_file named, the ECU powers up normalized with the
-- position start_position and the anti-pinch algorithm's learned state read from that file at time 0 (ap_restore:
-- the format is in antipinch.vhd's header), as an ECU that keeps its memory through a power cycle; a missing or
-- malformed file stops the run with "ecu_software: <file>:<line>: <reason>" (severity failure). With learned_out
-- named, the ECU writes that state there (ap_save, the file replaced) at a warm start and at the end of every run
-- once it is normalized (a stall, the end of a reversal): after the normalization, after the runs that refine the
-- reference and after those that learn the pole shares (algorithms 3-5 learn them in either direction). Only the VHDL
-- algorithms have a learned state the ECU can read and write: with algorithm 1 (C) both are refused at time 0.
--
-- Record and replay (docs/anti-pinch.md, "Record and replay"): with record_out named, the ECU writes one line per
-- activation by a Hall-A edge, a new command or a change of the current register (the PWM ECU's), "t_us hall_a
-- hall_b supply_dv command [current_code]" (its timer, the two Hall levels and the command as std_logic characters,
-- the supply register in 0.1 V or -1 when unknown, and with a current measured its ADC code), everything its
-- decisions rest on. With reverse_on_pinch = false a detection is held off (no reversal, no pinch flag): until a
-- reversal the plant does not depend on the algorithm, so such a record replays any algorithm (tb_replay).
--
-- Commands (switch, 4.3.3.2): command "00" stop, "01" up, "10" down, "11" one-touch up. The motor follows the
-- command; a stall (any direction) switches it off and so does the end of a reversal, and then the ECU
-- waits until the command changes before it obeys again (a new press of the switch). One-touch (express) closing:
-- "11" starts a run up that the released switch ("00") does not stop; it ends at the top's stall, in a reversal,
-- or when the switch asks for down (a press of "01" again keeps it running up).
--
-- Anti-pinch: the algorithm is the package antipinch (vhdl/digital/antipinch.vhd, docs/anti-pinch.md): the
-- ECU calls it at every start, at every Hall-A edge in the run's direction and when a run up ends in a stall
-- at the top; on a pinch the ECU reverses: down for reverse_mm, stop, pinch = '1' until the next start.
-- Anti-pinch is off until the ECU is normalized.
--
-- Outputs: relay_up/relay_down to ecu_hardware ("01" up, "10" down, both '0' stop); motor_state the same
-- coding as command ("00" stop, "01" up, "10" down); position [edges] as a 32-bit two's-complement vector
-- (a bench connects it straight to the switch's position input: digital-unit inputs must be vectors);
-- normalized; pinch.
--
-- Generics: integer/natural/boolean, and the file names learned_file, learned_out (empty, the default: none);
-- GHDL sets them with -gNAME=VALUE; units in the comments.
-- Limits: speed resolution 1 us per revolution; simulated time below 35.8 min (the 1 us timer); B must
-- not change in the same instant as A; reference tables cover reference_bins*edges_per_bin edges below the
-- top; no one-touch opening, no thermal protection, no relay timing (the relays switch in the
-- instant the state changes). A warm start trusts start_position: the position where the plant's glass and
-- cable loop are at t = 0, on the scale of the run that learned the state (the bench's business).
entity ecu_software is
  generic (
    stall_time_ms    : positive := ecu_software_stall_time_ms;     -- [ms] no Hall-A edge this long with a relay on = stall (5.2.1)
    edges_per_m      : positive := ecu_software_edges_per_m;       -- [1/m] Hall-A edges per metre of glass travel (2.112 per mm)
    no_pinch_zone_mm : natural  := ecu_software_no_pinch_zone_mm;  -- [mm] anti-pinch off this close below the top
    rpm_per_volt     : positive := ecu_software_rpm_per_volt;      -- [rpm/V] no-load armature speed per volt of supply
    threshold_rpm    : positive := ecu_software_threshold_rpm;     -- [rpm] speed deficit above the reference that is a pinch
    startup_rpm      : natural  := ecu_software_startup_rpm;       -- [rpm] extra threshold at a start, falling linearly to 0
    startup_ms       : natural  := ecu_software_startup_ms;        -- [ms] duration of that fall (0 = no extra threshold)
    blank_edges      : natural  := ecu_software_blank_edges;       -- [edges] no detection and no learning after a start
    edges_per_bin    : positive := ecu_software_edges_per_bin;     -- [edges] length of one bin of the reference
    reference_bins   : positive := ecu_software_reference_bins;    -- [1] number of bins (from the top down)
    learn_shift      : natural  := ecu_software_learn_shift;       -- [1] a later run up moves the reference by 1/2**learn_shift
    reverse_mm       : positive := ecu_software_reverse_mm;        -- [mm] travel down after a pinch
    max_run_edges    : positive := ecu_software_max_run_edges;     -- [edges] longest run up that is learned
    algorithm        : natural  := ecu_software_algorithm;         -- [1] anti-pinch: 0 the package's VHDL, 1 its C twin antipinch.c,
                                                                   --     2 the VHDL with the supply filtered (supply_tau_ms), 3 per
                                                                   --     edge, 4 the load observer, 5 the observer with a settled
                                                                   --     reference, 6 5 and its rise over one mode_ms,
                                                                   --     7 6 on the motor current (params/antipinch/*.txt)
    supply_tau_ms    : positive := ecu_software_supply_tau_ms;     -- [ms] algorithms 2-6: the drive's mechanical time constant J*ra/(ke*kt)
    mode_ms          : positive := ecu_software_mode_ms;           -- [ms] algorithms 5, 6: period of the glass swinging on its cable springs
    rpm_per_newton   : positive := ecu_software_rpm_per_newton;    -- [rpm/N] speed deficit per newton at the glass: scales `estimate`
    rpm_per_amp      : positive := ecu_software_rpm_per_amp;       -- [rpm/A] algorithm 7: speed deficit per ampere (ra/ke)
    current_lsb_ua   : positive := ecu_software_current_lsb_ua;    -- [uA] motor current per step of current_code
    learned_file     : string   := ecu_software_learned_file;      -- [-] warm start: the learned state to power up with ("": cold start)
    start_position   : integer  := ecu_software_start_position;    -- [edges] warm start: the position at power-up
    learned_out      : string   := ecu_software_learned_out;       -- [-] file the learned state is written to ("": none)
    reverse_on_pinch : boolean  := ecu_software_reverse_on_pinch;  -- [-] false: a detection is held off (recording)
    record_out       : string   := ecu_software_record_out);       -- [-] file the inputs are recorded to ("": none)
  port (
    hall_a, hall_b       : in std_logic;                     -- Hall signals (hall_sensor)
    supply_code          : in std_logic_vector(7 downto 0);  -- [0.1 V] supply voltage (ecu_hardware); the PWM ECU:
                                                              -- the mean voltage it drives the motor with
    current_code         : in std_logic_vector(9 downto 0);  -- [steps of current_lsb_ua,
                                                              -- 512 = 0 A] motor current (the PWM ECU's ecu_sense;
                                                              -- unconnected: none)
    command              : in std_logic_vector(1 downto 0);  -- switch: "00" stop, "01" up, "10" down
    relay_up, relay_down : out std_logic;                    -- relay coils (ecu_hardware)
    position             : out std_logic_vector(31 downto 0);-- [edges] electronic position (0 = top)
    normalized           : out std_logic;                    -- '1' once the top is known
    pinch                : out std_logic;                    -- '1' from a detection to the next start
    motor_state          : out std_logic_vector(1 downto 0); -- "00" stop, "01" up, "10" down
    estimate             : out std_logic_vector(15 downto 0));-- [0.1 N] the algorithm's load above its reference
                                                              -- as a force at the glass (signed), for plots
end entity ecu_software;

architecture behavioral of ecu_software is
  constant stall_us     : natural := stall_time_ms * 1000;
  constant start_us     : natural := startup_ms * 1000;
  constant zone_edges   : natural := no_pinch_zone_mm * edges_per_m / 1000;
  constant rev_edges    : natural := reverse_mm * edges_per_m / 1000;
  constant config       : ap_config := (algorithm => algorithm, rpm_per_volt => rpm_per_volt,
    threshold_rpm => threshold_rpm, startup_rpm => startup_rpm, start_us => start_us, blank_edges => blank_edges,
    edges_per_bin => edges_per_bin, reference_bins => reference_bins, learn_shift => learn_shift,
    max_run_edges => max_run_edges, zone_edges => zone_edges, supply_tau_us => supply_tau_ms * 1000,
    mode_us => mode_ms * 1000, rpm_per_amp => rpm_per_amp);

  type state_t is (stopped, up, down, reversing);

  -- x limited to lo .. hi (VHDL-2008's maximum/minimum are not VHDL-93, which 1076.1 tools analyse)
  function clamp(x, lo, hi : integer) return integer is
  begin
    if x < lo then
      return lo;
    elsif x > hi then
      return hi;
    end if;
    return x;
  end function clamp;

  -- [mA] the mean current over span us in which current_code integrated to sum [ADC steps from 512 x us]; code, the
  -- register now, where span is 0. To 1/1000 of a step: |sum| < 512*span and span <= 1e6 keep it within 2**31.
  function mean_ma(sum, span, code : integer) return integer is
    variable whole, milli : integer;
  begin
    if span <= 0 then
      milli := (code - 512) * 1000;
    else
      whole := sum / span;
      milli := whole * 1000 + (sum - whole * span) * 1000 / span;
    end if;
    return (2 * milli + 1000) * (current_lsb_ua / 100) / 20_000;   -- step k is (k - 511.5) steps of current
  end function mean_ma;
begin
  assert stall_time_ms <= 1_000_000 report "ecu_software: stall_time_ms must be <= 1000000" severity failure;
  assert startup_ms <= 1_000_000 and (startup_ms = 0 or startup_rpm <= integer'high / startup_ms)
    report "ecu_software: startup_ms must be <= 1000000 and startup_rpm*startup_ms < 2**31" severity failure;
  assert algorithm <= ap_algorithms - 1
    report "ecu_software: algorithm must be 0 .. " & integer'image(ap_algorithms - 1) & " (the antipinch package's "
           & "algorithms, docs/anti-pinch.md)" severity failure;
  assert supply_tau_ms <= 1000 report "ecu_software: supply_tau_ms must be <= 1000" severity failure;
  assert mode_ms <= 1000 report "ecu_software: mode_ms must be <= 1000" severity failure;
  assert reference_bins <= ap_max_bins and max_run_edges <= ap_max_run
    report "ecu_software: reference_bins and max_run_edges must fit the antipinch package's memory" severity failure;
  assert algorithm /= 1 or (learned_file'length = 0 and learned_out'length = 0)
    report "ecu_software: learned_file and learned_out need a VHDL algorithm (not 1): the C algorithm (1) keeps "
           & "its learned state in antipinch.c" severity failure;
  assert learned_file'length > 0 or start_position = 0
    report "ecu_software: start_position is the position of a warm start: it needs learned_file" severity failure;

  control: process
    variable t_us        : natural := 0;              -- [us] the timer at this activation (captured at an edge)
    variable a_old       : std_logic := 'U';          -- hall_a at the previous activation
    variable pos         : integer := 0;              -- electronic position [edges]
    variable is_norm     : boolean := false;
    variable state       : state_t := stopped;
    variable locked      : boolean := false;          -- ignore the command until it changes
    variable express     : boolean := false;          -- a one-touch run up: a released switch does not stop it
    variable lock_cmd    : std_logic_vector(1 downto 0) := "00";
    variable last_edge   : natural := 0;              -- [us] the last Hall-A edge of the run (or its start)
    variable run_edges   : natural := 0;              -- Hall-A edges in the run's direction
    variable reverse_to  : integer := 0;              -- position where a reversal ends
    variable pinch_flag  : std_logic := '0';
    variable memory      : ap_memory := ap_initial;   -- the anti-pinch algorithm's memory
    variable cmd         : std_logic_vector(1 downto 0);
    variable step        : integer;
    variable supply_dv   : integer;
    variable current_ma  : integer;
    variable i_sum       : integer := 0;              -- [ADC steps from 512 x us] current_code integrated since ...
    variable i_from      : natural := 0;              -- [us] ... this time (the run's last edge in its direction)
    variable i_t         : natural := 0;              -- [us] current_code's last change seen (or i_from)
    variable i_code      : integer := 512;            -- [ADC steps] current_code since i_t
    variable detected    : boolean;
    file learned         : text;
    variable status      : file_open_status;
    variable line_no     : natural;
    variable why         : line;
    file recording       : text;
    variable rec_line    : line;
    variable rec_a       : std_logic := 'U';          -- hall_a and the command at the last recorded activation
    variable rec_cmd     : std_logic_vector(1 downto 0) := "UU";
    variable rec_i       : std_logic_vector(9 downto 0) := (others => 'U');

    -- Start a run in direction s (up, down or reversing): clears the run buffer, and the pinch flag
    -- unless s is the reversal.
    procedure start(s : state_t) is
    begin
      state := s;
      express := false;
      last_edge := t_us;
      run_edges := 0;
      i_sum := 0;
      i_from := t_us;
      i_t := t_us;
      ap_start(memory, config, t_us, pos);
      if s /= reversing then
        pinch_flag := '0';
      end if;
    end procedure start;

    -- Write the learned state to learned_out (if named), replacing the file.
    procedure save is
    begin
      if learned_out'length > 0 then
        file_open(status, learned, learned_out, write_mode);
        assert status = open_ok report "ecu_software: cannot write " & learned_out & " (learned_out)" severity failure;
        ap_save(learned, memory, config);
        file_close(learned);
      end if;
    end procedure save;

    -- Switch the motor off and wait for a changed command.
    procedure halt is
    begin
      state := stopped;
      locked := true;
      lock_cmd := cmd;
      if is_norm then
        save;     -- what the algorithm learned in this run (a run down may learn too: the pole shares)
      end if;
    end procedure halt;

  begin
    if record_out'length > 0 then
      file_open(status, recording, record_out, write_mode);
      assert status = open_ok report "ecu_software: cannot write " & record_out & " (record_out)" severity failure;
      write(rec_line, string'("# ecu_software input record: t_us hall_a hall_b supply_dv command"));
      writeline(recording, rec_line);
      file_close(recording);
    end if;
    if learned_file'length > 0 then   -- warm start: normalized at start_position, with the learned state
      file_open(status, learned, learned_file, read_mode);
      assert status = open_ok report "ecu_software: cannot open " & learned_file & " (learned_file)" severity failure;
      ap_restore(learned, memory, config, line_no, why);
      file_close(learned);
      if why /= null then
        report "ecu_software: " & learned_file & ":" & integer'image(line_no) & ": " & why.all severity failure;
      end if;
      pos := start_position;
      is_norm := true;
      save;
    end if;
    loop
      t_us := now / 1 us;
      cmd := command;
      if cmd /= "01" and cmd /= "10" and cmd /= "11" then
        cmd := "00";  -- metavalues: stop
      end if;
      -- The current measured: the ADC's conversions averaged over each edge's period, as the register integrated
      -- over time (the mean of a converter sampling at the PWM's instants; the register changes at its steps).
      if not is_x(current_code) then
        if t_us - i_from > 1_000_000 then   -- a second without an edge of a run: start the mean anew
          i_sum := 0;
          i_from := t_us;
          i_t := t_us;
        end if;
        i_sum := i_sum + (i_code - 512) * (t_us - i_t);
        i_t := t_us;
        i_code := to_integer(unsigned(current_code));
      end if;
      if record_out'length > 0 and (hall_a /= rec_a or command /= rec_cmd or current_code /= rec_i) then
        rec_a := hall_a;
        rec_cmd := command;
        rec_i := current_code;
        supply_dv := -1;
        if not is_x(supply_code) then
          supply_dv := to_integer(unsigned(supply_code));
        end if;
        write(rec_line, t_us);
        write(rec_line, ' ' & std_logic'image(hall_a)(2) & ' ' & std_logic'image(hall_b)(2) & ' ');
        write(rec_line, supply_dv);
        write(rec_line, ' ' & std_logic'image(command(1))(2) & std_logic'image(command(0))(2));
        if not is_x(current_code) then   -- the PWM ECU's current, in ADC steps
          write(rec_line, ' ' & integer'image(to_integer(unsigned(current_code))));
        end if;
        file_open(status, recording, record_out, append_mode);  -- each line closed at once: a co-simulation
        writeline(recording, rec_line);                           -- may end without closing the ECU's files
        file_close(recording);
      end if;
      if locked and cmd /= lock_cmd then
        locked := false;
      end if;

      -- Hall-A edge: count; on an edge in the run's direction measure the speed, learn and detect.
      if (hall_a = '0' or hall_a = '1') and (a_old = '0' or a_old = '1') and hall_a /= a_old then
        if hall_a /= hall_b then
          step := 1;   -- positive rotation: lifting
        else
          step := -1;  -- negative rotation: lowering
        end if;
        pos := pos - step;
        if (state = up and step = 1) or ((state = down or state = reversing) and step = -1) then
          last_edge := t_us;
          run_edges := run_edges + 1;
          supply_dv := -1;
          if not is_x(supply_code) then
            supply_dv := to_integer(unsigned(supply_code));
          end if;
          current_ma := ap_no_current;
          if not is_x(current_code) then
            current_ma := mean_ma(i_sum, t_us - i_from, i_code);
            i_sum := 0;
            i_from := t_us;
          end if;
          ap_edge(memory, config, t_us, pos, run_edges, state = up, supply_dv, current_ma, is_norm, detected);
          if detected and reverse_on_pinch then
            start(reversing);
            reverse_to := pos + rev_edges;
            pinch_flag := '1';
          end if;
        end if;
      end if;
      a_old := hall_a;

      -- End of a reversal; stall (no edge in the run's direction for stall_time_ms).
      if state = reversing and pos >= reverse_to then
        halt;
      elsif state /= stopped and t_us - last_edge >= stall_us then
        if state = up and not is_norm then
          ap_top(memory, config, pos);  -- the learning run of the normalization: the stall is the top
          pos := 0;
          is_norm := true;
        elsif state = up and pos <= zone_edges then
          ap_top(memory, config, 0);    -- a run up that reached the top refines the reference
        end if;
        halt;
      end if;

      -- Commands (a reversal runs to its end).
      case state is
        when stopped =>
          if not locked and (cmd = "01" or cmd = "11") then
            start(up);
            express := cmd = "11";
          elsif not locked and cmd = "10" then
            start(down);
          end if;
        when up =>
          if cmd = "10" then
            start(down);
          elsif cmd = "00" and not express then
            state := stopped;
          end if;
        when down =>
          if cmd = "01" or cmd = "11" then
            start(up);
            express := cmd = "11";
          elsif cmd = "00" then
            state := stopped;
          end if;
        when reversing =>
          null;
      end case;

      -- Outputs (also at the first activation, so they are defined from time 0).
      if state = up then
        relay_up <= '1';
        relay_down <= '0';
        motor_state <= "01";
      elsif state = down or state = reversing then
        relay_up <= '0';
        relay_down <= '1';
        motor_state <= "10";
      else
        relay_up <= '0';
        relay_down <= '0';
        motor_state <= "00";
      end if;
      position <= std_logic_vector(to_signed(pos, 32));
      estimate <= std_logic_vector(to_signed(
        clamp(ap_load(memory, config) * 10 / rpm_per_newton, -32768, 32767), 16));
      pinch <= pinch_flag;
      if is_norm then
        normalized <= '1';
      else
        normalized <= '0';
      end if;

      -- Sleep until an interrupt: a Hall-A edge, a new command, or the stall compare timer of a run.
      if state = stopped then
        wait on hall_a, command;
      else
        wait on hall_a, command, current_code for (last_edge + stall_us - t_us) * 1 us;
      end if;
    end loop;
  end process control;
end architecture behavioral;
