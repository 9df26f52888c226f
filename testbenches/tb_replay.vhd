library IEEE;
use IEEE.STD_LOGIC_1164.all;
use IEEE.NUMERIC_STD.all;
use std.textio.all;
use work.wr_digital_params.all;

-- tb_replay: the ECU software (ecu_software, with its anti-pinch algorithm) run by GHDL alone on a record of its
-- inputs instead of the plant (docs/anti-pinch.md, "Record and replay"). Until the ECU reverses, a closing does not
-- depend on the algorithm: it only sees Hall-A edges, the level of Hall B at them, the supply register and the
-- command. A record made in closed loop with the reversal held off (tb_closed_loop's record_out and
-- reverse_on_pinch = false), or taken from a real door in the same format, therefore tells where any algorithm
-- would have reversed, in milliseconds instead of a closed-loop run.
--
-- Record (record_file): one line per activation of the ECU, "t_us hall_a hall_b supply_dv command [current_code]"
-- (ecu_software's record_out: the 1 us timer, the Hall levels and the two command bits as std_logic characters, the
-- supply in 0.1 V, -1 unknown, and a PWM ECU's motor current as its ADC code, 0 .. 1023); lines starting with '#' are
-- comments; times must not decrease.
-- Result (result_file): "pinch T_US POSITION" at the first detection (the replay stops feeding the record there:
-- after a reversal the recorded inputs no longer hold), else "end T_US" after the last record line and one stall
-- time. Plain VHDL-93 (no std.env): the simulation ends when the ECU has halted and nothing is left to happen. A malformed
-- record stops the run with "tb_replay: <file>:<line>: <reason>" (severity failure).
-- Generics: the ECU's (ecu_software; defaults from wr_digital_params, GHDL sets them with -gNAME=VALUE), and the
-- two files.
-- bench: none (wrsim.benches.replay runs it; tests/acceptance/test_replay_closed_loop.py)
entity tb_replay is
  generic (
    record_file      : string   := "record.txt";                   -- [-] the ECU's inputs (format above)
    result_file      : string   := "replay.txt";                   -- [-] where the first detection is written
    stall_time_ms    : positive := ecu_software_stall_time_ms;     -- [ms] the ECU's generics (ecu_software)
    edges_per_m      : positive := ecu_software_edges_per_m;       -- [1/m]
    no_pinch_zone_mm : natural  := ecu_software_no_pinch_zone_mm;  -- [mm]
    rpm_per_volt     : positive := ecu_software_rpm_per_volt;      -- [rpm/V]
    threshold_rpm    : positive := ecu_software_threshold_rpm;     -- [rpm]
    startup_rpm      : natural  := ecu_software_startup_rpm;       -- [rpm]
    startup_ms       : natural  := ecu_software_startup_ms;        -- [ms]
    blank_edges      : natural  := ecu_software_blank_edges;       -- [edges]
    edges_per_bin    : positive := ecu_software_edges_per_bin;     -- [edges]
    reference_bins   : positive := ecu_software_reference_bins;    -- [1]
    learn_shift      : natural  := ecu_software_learn_shift;       -- [1]
    reverse_mm       : positive := ecu_software_reverse_mm;        -- [mm]
    max_run_edges    : positive := ecu_software_max_run_edges;     -- [edges]
    algorithm        : natural  := ecu_software_algorithm;         -- [1]
    supply_tau_ms    : positive := ecu_software_supply_tau_ms;     -- [ms]
    mode_ms          : positive := ecu_software_mode_ms;           -- [ms]
    rpm_per_newton   : positive := ecu_software_rpm_per_newton;    -- [rpm/N]
    rpm_per_amp      : positive := ecu_software_rpm_per_amp;       -- [rpm/A]
    current_lsb_ua   : positive := ecu_software_current_lsb_ua;    -- [uA]
    learned_file     : string   := ecu_software_learned_file;      -- [-]
    start_position   : integer  := ecu_software_start_position;    -- [edges]
    learned_out      : string   := ecu_software_learned_out);      -- [-]
end entity tb_replay;

architecture bench of tb_replay is
  signal hall_a, hall_b       : std_logic := 'U';
  signal supply_code          : std_logic_vector(7 downto 0) := (others => 'U');
  signal current_code         : std_logic_vector(9 downto 0) := (others => 'U');
  signal command              : std_logic_vector(1 downto 0) := "UU";
  signal relay_up, relay_down : std_logic;
  signal position             : std_logic_vector(31 downto 0);
  signal normalized, pinch    : std_logic;
  signal motor_state          : std_logic_vector(1 downto 0);
  signal estimate             : std_logic_vector(15 downto 0);
  file result                 : text open write_mode is result_file;

  -- The next character of l that is not a blank (NUL when the line is used up).
  procedure next_char(l : inout line; c : out character) is
    variable ok : boolean := true;
    variable ch : character := ' ';
  begin
    while ok and (ch = ' ' or ch = HT) loop
      read(l, ch, ok);
    end loop;
    if not ok then
      ch := NUL;
    end if;
    c := ch;
  end procedure next_char;

  -- The std_logic of character c; ok = false when c is none.
  procedure logic(c : character; v : out std_logic; ok : out boolean) is
    constant names : string(1 to 9) := "UX01ZWLH-";
    constant values : std_logic_vector(1 to 9) := "UX01ZWLH-";
  begin
    ok := false;
    v := 'U';
    for k in names'range loop
      if names(k) = c then
        v := values(k);
        ok := true;
      end if;
    end loop;
  end procedure logic;

begin
  ecu: entity work.ecu_software
    generic map (stall_time_ms => stall_time_ms, edges_per_m => edges_per_m, no_pinch_zone_mm => no_pinch_zone_mm,
                 rpm_per_volt => rpm_per_volt, threshold_rpm => threshold_rpm, startup_rpm => startup_rpm,
                 startup_ms => startup_ms, blank_edges => blank_edges, edges_per_bin => edges_per_bin,
                 reference_bins => reference_bins, learn_shift => learn_shift, reverse_mm => reverse_mm,
                 max_run_edges => max_run_edges, algorithm => algorithm, supply_tau_ms => supply_tau_ms,
                 mode_ms => mode_ms, rpm_per_newton => rpm_per_newton, rpm_per_amp => rpm_per_amp,
                 current_lsb_ua => current_lsb_ua, learned_file => learned_file, start_position => start_position,
                 learned_out => learned_out)
    port map (hall_a => hall_a, hall_b => hall_b, supply_code => supply_code, current_code => current_code,
              command => command,
              relay_up => relay_up, relay_down => relay_down, position => position,
              normalized => normalized, pinch => pinch, motor_state => motor_state, estimate => estimate);

  drive: process
    file inputs      : text;
    variable status  : file_open_status;
    variable l       : line;
    variable line_no : natural := 0;
    variable t_us    : integer;
    variable supply  : integer;
    variable amps    : integer;         -- the current's ADC code (-1: none on the line)
    variable ok      : boolean;
    variable c       : character;
    variable a, b    : std_logic;
    variable cmd     : std_logic_vector(1 downto 0);
    variable good    : boolean;

    procedure fail(why : string) is
    begin
      report "tb_replay: " & record_file & ":" & integer'image(line_no) & ": " & why severity failure;
    end procedure fail;
  begin
    file_open(status, inputs, record_file, read_mode);
    assert status = open_ok report "tb_replay: cannot open " & record_file & " (record_file)" severity failure;
    while not endfile(inputs) loop
      readline(inputs, l);
      line_no := line_no + 1;
      next_char(l, c);
      if c /= NUL and c /= '#' then
        l := new string'(c & l.all);
        read(l, t_us, ok);
        if not ok or t_us < 0 then
          fail("expected the time [us], a natural number");
        end if;
        if t_us * 1 us < now then
          fail("time " & integer'image(t_us) & " us goes back (the last line was at " & time'image(now) & ")");
        end if;
        next_char(l, c);
        logic(c, a, good);
        next_char(l, c);
        logic(c, b, ok);
        good := good and ok;
        read(l, supply, ok);
        good := good and ok and supply >= -1 and supply <= 255;
        for k in 1 downto 0 loop
          next_char(l, c);
          logic(c, cmd(k), ok);
          good := good and ok;
        end loop;
        next_char(l, c);
        amps := -1;
        if c /= NUL then   -- the current (a PWM ECU's record)
          l := new string'(c & l.all);
          read(l, amps, ok);
          good := good and ok and amps >= 0 and amps <= 1023;
          next_char(l, c);
        end if;
        if not good or c /= NUL then
          fail("expected 't_us hall_a hall_b supply_dv command [current_code]', e.g. '125000 1 0 130 01'");
        end if;
        wait for t_us * 1 us - now;
        exit when pinch = '1';  -- after a reversal the recorded inputs no longer hold
        hall_b <= b;
        if supply < 0 then
          supply_code <= (others => 'X');
        else
          supply_code <= std_logic_vector(to_unsigned(supply, 8));
        end if;
        if amps >= 0 then
          current_code <= std_logic_vector(to_unsigned(amps, 10));
        end if;
        command <= cmd;
        hall_a <= a;
      end if;
    end loop;
    file_close(inputs);
    if pinch /= '1' then
      wait for stall_time_ms * 1 ms + 1 ms;
    end if;
    if pinch /= '1' then
      write(l, "end " & integer'image(now / 1 us));
      writeline(result, l);
      file_close(result);
    end if;
    wait;  -- the ECU halts at its stall time at the latest, and the simulation ends without events
  end process drive;

  watch: process
    variable l : line;
  begin
    wait until pinch = '1';
    write(l, "pinch " & integer'image(now / 1 us) & " " & integer'image(to_integer(signed(position))));
    writeline(result, l);
    file_close(result);
    wait;
  end process watch;
end architecture bench;
