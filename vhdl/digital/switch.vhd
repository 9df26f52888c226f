library IEEE;
use IEEE.STD_LOGIC_1164.all;
use IEEE.NUMERIC_STD.all;
use STD.TEXTIO.all;
use work.wr_digital_params.all;

-- switch: the electrical window switch of the system bench as a sequence of instructions (thesis
-- 4.3.3.2): "model of switch provides the possibility to create a sequence of instruction, which are sent
-- into electronics"; instruction 0 stop, 1 up, 2 down; no difference between manual and automatic
-- operation. Digital VHDL-2008, run by GHDL (mixed-signal contract, docs/vhdl-ams-subset.md).
--
-- Sequence file (sequence_file, read with std.textio; full description in docs/switch-sequence.md). One
-- unit per line, fields separated by blanks; blank lines and everything from '#' to the end of a line are
-- ignored:
--   T <time s> <command> [<voltage offset V>]
--       time-based unit: at the simulation time <time> [s] the command becomes <command> (0 stop, 1 up,
--       2 down, 3 one-touch up: a short press of the switch's second detent, "11") and stays until the next unit; the voltage offset is <voltage offset> during the unit, 0 V
--       when the field is left out (the thesis's time unit has no voltage field; this project adds it so that
--       a sequence can dip the supply while the motor runs, e.g. at an engine crank). The unit ends at the
--       time of the next T unit, or at once when a P unit follows. A T unit that repeats the command does
--       not change it (the ECU sees no new command).
--   P <target position m> <voltage offset V> <reserved> <timeout s>
--       position/voltage-based unit: drive toward the target electronic position (the ECU's position,
--       0 = top, positive = below the top; converted to Hall edges with edges_per_m) with the battery
--       voltage offset by <voltage offset> (0.1 V steps, -12.8 .. 12.7 V); up while the position is
--       above the target (position > target), down while below, stop once it is reached or passed.
--       The unit is cancelled when the position has not changed for <timeout> [s] (> 0); then the switch
--       is released (command 0) for release_ms and the next unit starts. <reserved> is read and unused.
--   Example: the thesis's time sequence (0, 0), (0.1, 1), (4.5, 0) is "T 0.0 0", "T 0.1 1", "T 4.5 0";
--   "P 0.0 -4 0 0.6" closes the window at 13 - 4 = 9 V.
-- The file is checked completely before the first unit runs: a malformed line (wrong kind, missing or
-- extra field, non-number, timeout <= 0, offset outside the range), an unknown command, or T times that do
-- not increase strictly stop the simulation with "switch: <file>:<line>: <reason>" (severity failure).
-- Every unit reports "switch: line <n>: ..." when it starts; "switch: sequence finished" after the last.
--
-- Outputs: command ("00" stop, "01" up, "10" down, "11" one-touch up) to the ECU; voltage_offset (signed, 0.1 V per step) to
-- the supply, so that one run can test 9, 13 and 16 V (5.3.2). After the sequence the command is "00"
-- (after a P unit) or that of the last T unit.
--
-- Position input: the ECU's electronic position as a 32-bit two's-complement vector, connected directly
-- to ecu_software's position output of the same type (GHDL 2.0 cannot set an integer input through VPI,
-- so the mixed-signal contract has no integer inputs). While the position is undefined (metavalues, e.g. before the ECU's first activation at time 0) a P unit commands stop.
--
-- Generics: sequence_file (path, relative to the simulator's working directory), edges_per_m (as the ECU:
-- 2112 Hall-A edges per metre), release_ms.
-- Limits: the thesis's example "(0.500, 0, 0, 0.6): go up to 500 mm from position 0" reads like a glass
-- height; the switch sees only the ECU's position, so its targets are electronic positions (counted from
-- the top downwards, Fig. 5.3; docs/switch-sequence.md). T units are events in simulation time, P units
-- follow the glass; a T unit reached after its time starts at once (warning).
entity switch is
  generic (
    sequence_file : string   := switch_sequence_file;  -- [-] path of the sequence file
    edges_per_m   : positive := switch_edges_per_m;    -- [1/m] Hall-A edges per metre of glass travel
    release_ms    : natural  := switch_release_ms);    -- [ms] command "00" after each P unit
  port (
    position       : in std_logic_vector(31 downto 0);  -- [edges] ECU position, two's complement
    command        : out std_logic_vector(1 downto 0);  -- "00" stop, "01" up, "10" down, "11" one-touch up
    voltage_offset : out std_logic_vector(7 downto 0)); -- [0.1 V] signed supply offset
end entity switch;

architecture behavioral of switch is
  -- One unit of the sequence as read from the file.
  type unit_t is record
    kind    : character;  -- 'T', 'P' or ' ' (no unit on this line)
    time    : real;       -- [s] T: start time
    command : integer;    -- T: 0 stop, 1 up, 2 down, 3 one-touch up
    target  : real;       -- [m] P: target electronic position
    offset  : integer;    -- [0.1 V] voltage offset
    timeout : real;       -- [s] P: cancel after no position change for this long
  end record unit_t;

  -- Command code for the ECU.
  function code(c : integer) return std_logic_vector is
  begin
    case c is
      when 1 => return "01";
      when 2 => return "10";
      when 3 => return "11";
      when others => return "00";
    end case;
  end function code;

  -- Remove blanks (space, tab) at the front of l.
  procedure skip_blanks(l : inout line) is
    variable ch : character;
  begin
    while l'length > 0 and (l(l'left) = ' ' or l(l'left) = HT) loop
      read(l, ch);
    end loop;
  end procedure skip_blanks;

  -- Read a number in any of the usual forms (0, -3, 1., .5, 1e3, 1.5e-3) from l: std.textio's read
  -- for real wants a digit on both sides of the point, so the token is completed to that form first.
  procedure read_number(l : inout line; value : out real; ok : out boolean) is
    variable good  : boolean;   -- (an out parameter is not read: VHDL-93, which 1076.1 tools analyse)
    variable token : line;
    variable lit   : line;
    variable ch    : character;
    variable exp   : natural;
    variable point : boolean;
  begin
    skip_blanks(l);
    token := new string'("");
    while l'length > 0 and l(l'left) /= ' ' and l(l'left) /= HT loop
      read(l, ch);
      write(token, ch);
    end loop;
    exp := token'length + 1;  -- position of the exponent marker (none: after the end)
    point := false;
    for k in token'length downto 1 loop
      if token(k) = 'e' or token(k) = 'E' then
        exp := k;
      elsif token(k) = '.' then
        point := true;
      end if;
    end loop;
    lit := new string'("");
    for k in 1 to exp - 1 loop
      if token(k) = '.' and (k = 1 or token(k - 1) < '0' or token(k - 1) > '9') then
        write(lit, character'('0'));  -- ".5" -> "0.5"
      end if;
      write(lit, token(k));
      if token(k) = '.' and (k = exp - 1 or token(k + 1) < '0' or token(k + 1) > '9') then
        write(lit, character'('0'));  -- "1." -> "1.0"
      end if;
    end loop;
    if not point then
      write(lit, string'(".0"));  -- "3" -> "3.0"
    end if;
    for k in exp to token'length loop
      write(lit, token(k));
    end loop;
    ok := false;
    value := 0.0;
    if token'length > 0 then
      read(lit, value, good);
      ok := good and lit'length = 0;
    end if;
    deallocate(token);
    deallocate(lit);
  end procedure read_number;

  -- Parse one line: why = null for a unit or an empty line (u.kind = ' '), else the reason it is malformed
  -- (u and why are inout because the procedure reads them back: VHDL-93 reads no out parameter).
  procedure parse(text : inout line; u : inout unit_t; why : inout line) is
    variable l        : line;
    variable ch       : character;
    variable ok       : boolean;
    variable reserved : real;
    variable volts    : real;
    variable cut      : natural;
  begin
    u := (kind => ' ', time => 0.0, command => 0, target => 0.0, offset => 0, timeout => 0.0);
    why := null;
    cut := 0;
    for k in 1 to text'length loop  -- the comment starts at the first '#'
      if cut = 0 and text(text'low + k - 1) = '#' then
        cut := k;
      end if;
    end loop;
    if cut > 0 then
      l := new string'(text(text'low to text'low + cut - 2));
    else
      l := new string'(text.all);
    end if;
    if l'length > 256 then  -- std.textio reads and copies the rest of a line per character: a bound keeps it fast
      why := new string'("a unit longer than 256 characters (before its comment)");
      deallocate(l);
      return;
    end if;
    skip_blanks(l);
    if l'length = 0 then
      deallocate(l);
      return;
    end if;
    read(l, ch);
    if ch = 'T' or ch = 't' then
      u.kind := 'T';
      read_number(l, u.time, ok);
      if ok then
        read(l, u.command, ok);
      end if;
      volts := 0.0;
      skip_blanks(l);
      if ok and l'length > 0 then
        read_number(l, volts, ok);
      end if;
      if not ok then
        why := new string'("malformed T unit, expected: T <time s> <command> [<voltage offset V>]");
      elsif u.command < 0 or u.command > 3 then
        why := new string'("unknown command " & integer'image(u.command) & " (0 stop, 1 up, 2 down, 3 one-touch up)");
      elsif volts < -12.8 or volts > 12.7 then
        why := new string'("voltage offset must be in -12.8 .. 12.7 V");
      else
        u.offset := integer(volts * 10.0);
      end if;
    elsif ch = 'P' or ch = 'p' then
      u.kind := 'P';
      read_number(l, u.target, ok);
      if ok then
        read_number(l, volts, ok);
      end if;
      if ok then
        read_number(l, reserved, ok);
      end if;
      if ok then
        read_number(l, u.timeout, ok);
      end if;
      if not ok then
        why := new string'("malformed P unit, expected: P <target position m> <voltage offset V> "
                           & "<reserved> <timeout s>");
      elsif u.timeout <= 0.0 then
        why := new string'("timeout must be > 0 s");
      elsif volts < -12.8 or volts > 12.7 then
        why := new string'("voltage offset must be in -12.8 .. 12.7 V");
      else
        u.offset := integer(volts * 10.0);
      end if;
    else
      why := new string'("unknown unit '" & ch & "', expected T or P");
    end if;
    if why = null then
      skip_blanks(l);
      if l'length > 0 then
        why := new string'("unexpected text '" & l.all & "' after the unit");
      end if;
    end if;
    deallocate(l);
  end procedure parse;
begin
  run: process
    file f          : text;
    variable status : file_open_status;
    variable l      : line;
    variable why    : line;
    variable u      : unit_t;
    variable next_u : unit_t;
    variable n      : natural;
    variable last_t : real;
    variable have_t : boolean;
    variable target  : integer;                       -- [edges] P: target position
    variable p       : integer;                       -- [edges] P: position
    variable seen    : std_logic_vector(31 downto 0); -- P: position at the last change
    variable going   : std_logic_vector(1 downto 0);  -- P: "01" up, "10" down, "00" not chosen yet
    variable reached : boolean;                       -- P: target reached or passed
    variable left    : time;                          -- P: time left until the timeout

    -- Read the next unit (skipping empty lines) into next_u; next_u.kind = ' ' at the end of the file.
    procedure fetch is
    begin
      next_u.kind := ' ';
      while next_u.kind = ' ' and not endfile(f) loop
        readline(f, l);
        n := n + 1;
        parse(l, next_u, why);
        if why /= null then
          report "switch: " & sequence_file & ":" & integer'image(n) & ": " & why.all severity failure;
        end if;
      end loop;
    end procedure fetch;
  begin
    command <= "00";
    voltage_offset <= (others => '0');
    -- Pass 1: check the whole file.
    file_open(status, f, sequence_file, read_mode);
    assert status = open_ok report "switch: cannot open sequence file " & sequence_file severity failure;
    n := 0;
    have_t := false;
    last_t := 0.0;
    loop
      fetch;
      exit when next_u.kind = ' ';
      if next_u.kind = 'T' then
        assert not have_t or next_u.time > last_t
          report "switch: " & sequence_file & ":" & integer'image(n) & ": time " & real'image(next_u.time)
                 & " s does not follow " & real'image(last_t) & " s" severity failure;
        assert next_u.time >= 0.0
          report "switch: " & sequence_file & ":" & integer'image(n) & ": time must be >= 0 s"
          severity failure;
        have_t := true;
        last_t := next_u.time;
      end if;
    end loop;
    file_close(f);

    -- Pass 2: run the units.
    file_open(f, sequence_file, read_mode);
    n := 0;
    fetch;
    while next_u.kind /= ' ' loop
      u := next_u;
      if u.kind = 'T' then
        if u.time * 1 sec > now then
          wait for u.time * 1 sec - now;
        elsif u.time * 1 sec < now then
          report "switch: line " & integer'image(n) & ": time " & real'image(u.time)
                 & " s has passed, the unit starts now" severity warning;
        end if;
        if u.offset = 0 then
          report "switch: line " & integer'image(n) & ": T unit, command " & integer'image(u.command);
        else
          report "switch: line " & integer'image(n) & ": T unit, command " & integer'image(u.command)
                 & ", offset " & integer'image(u.offset) & " x 0.1 V";
        end if;
        command <= code(u.command);
        voltage_offset <= std_logic_vector(to_signed(u.offset, 8));
        fetch;
        if next_u.kind = 'T' then  -- a T unit lasts until the time of the next one
          if next_u.time * 1 sec > now then
            wait for next_u.time * 1 sec - now;
          end if;
        end if;
      else
        target := integer(u.target * real(edges_per_m));
        report "switch: line " & integer'image(n) & ": P unit, target " & integer'image(target)
               & " edges, offset " & integer'image(u.offset) & " x 0.1 V";
        voltage_offset <= std_logic_vector(to_signed(u.offset, 8));
        going := "00";  -- direction, chosen at the first known position
        reached := false;
        seen := position;
        left := u.timeout * 1 sec;
        loop
          if not reached and not is_x(position) then
            p := to_integer(signed(position));
            if going = "00" then
              if p > target then
                going := "01";
              elsif p < target then
                going := "10";
              else
                reached := true;
              end if;
            elsif (going = "01" and p <= target) or (going = "10" and p >= target) then
              reached := true;
            end if;
          end if;
          if reached then
            command <= "00";
          else
            command <= going;
          end if;
          exit when left = 0 ns;
          wait on position for left;
          if position /= seen then  -- moved: the timeout starts again
            seen := position;
            left := u.timeout * 1 sec;
          else
            left := 0 ns;             -- no change for the timeout: the unit is cancelled
          end if;
        end loop;
        if is_x(position) then
          report "switch: line " & integer'image(n) & ": P unit ends, position unknown";
        else
          report "switch: line " & integer'image(n) & ": P unit ends at position "
                 & integer'image(to_integer(signed(position)));
        end if;
        command <= "00";
        wait for release_ms * 1 ms;
        fetch;
      end if;
    end loop;
    file_close(f);
    report "switch: sequence finished";
    wait;
  end process run;
end architecture behavioral;
