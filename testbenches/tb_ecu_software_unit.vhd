library IEEE;
use IEEE.STD_LOGIC_1164.all;
use IEEE.NUMERIC_STD.all;
use IEEE.MATH_REAL.all;

-- tb_ecu_software_unit: self-checking GHDL unit test of ecu_software (pure VHDL-2008, no AMS): Hall edges
-- in -> position counter, normalization, anti-pinch reversal out.
--   ghdl-llvm -a --std=08 vhdl/digital/wr_digital_params.vhd vhdl/digital/antipinch.vhd
--                         vhdl/digital/ecu_software.vhd testbenches/tb_ecu_software_unit.vhd
--   gcc -c -fPIC vhdl/digital/antipinch.c           (the C twin of the algorithm, see vhdl/digital/antipinch.vhd)
--   ghdl-llvm -e --std=08 -Wl,antipinch.o tb_ecu_software_unit
--   ./tb_ecu_software_unit --assert-level=error      (-galgorithm=1: the ECU runs the C twin)
--   (-glearned_out=FILE: the ECU writes its learned state there; -glearned_file=FILE -gstart_position=N: a warm
--   start from that state, see 5.)
-- Exit status 0 and the last line "tb_ecu_software_unit: all checks passed" mean success; every failed
-- check is an assertion of severity error naming what was expected.
--
-- The plant is a stand-in written in plain VHDL, NOT the window-regulator model: a first-order motor speed
-- n' = (n_ss - n)/tau with n_ss = rpm_per_volt*U_motor - load (the DC motor line in the ECU's own terms,
-- load in rpm of speed deficit), the glass on a rigid drive (travel per armature revolution
-- pi*44 mm/73), a load deficit rising along the stroke, a stiff top frame at 0.40 m, a bottom stop at 0,
-- and an obstacle spring (10 N/mm, taken as 13 rpm of deficit per N, the order of the FPG2 drive) at
-- 0.36 m when enabled. Hall A/B are generated from the armature angle with a quarter-period (1/8 rev)
-- shift, as hall_sensor does. It exercises the ECU's logic; the anti-pinch numbers of the real system come
-- from the system bench.
--
-- Sequence and checks:
--   1. up at 13 V from the bottom (position 0, not normalized): the counter runs negative; after the stall
--      in the frame normalized = '1' and position = 0 (thesis 5.2.1).
--   2. down to the bottom: the counter runs up to the stroke (within 2 edges of the normalization count).
--   3. up at 16 V without obstacle: no pinch, stops at the top (|position| <= 3).
--   4. for 9, 13 and 16 V: down to the bottom, then up into the obstacle: pinch = '1', the ECU drives
--      down by reverse_mm (211 edges, +-4) and stops; peak obstacle force < 100 N; pinch detected within
--      8 mm of the obstacle.
--   5. a warm start (learned_file set): the ECU powers up normalized at start_position with the learned state
--      of the file (the plant starts at the bottom, as after 2.); steps 1-3 are left out, step 4 runs.
-- bench: none (GHDL unit bench of the ECU software, tests/unit/test_ecu_vhdl.py)
entity tb_ecu_software_unit is
  generic (
    algorithm      : natural := 0;    -- [1] the ECU's anti-pinch implementation: 0 VHDL, 1 C (antipinch.c)
    learned_file   : string  := "";   -- [-] the ECU's warm start from this learned state ("": cold start)
    start_position : integer := 0;    -- [edges] the ECU's position at a warm start
    learned_out    : string  := "");  -- [-] the ECU writes its learned state here ("": not at all)
end entity tb_ecu_software_unit;

architecture bench of tb_ecu_software_unit is
  constant dt          : time := 5 us;             -- plant integration step (edges within 0.2 % of an edge)
  constant dt_s        : real := 5.0e-6;           -- [s] the same step
  constant tau         : real := 0.015;            -- [s] mechanical time constant of the plant
  constant rpm_per_v   : real := 449.0;            -- [rpm/V] no-load speed per volt (as the ECU's default)
  constant m_per_rev   : real := math_pi * 0.044 / 73.0;  -- [m] glass travel per armature revolution
  constant x_top       : real := 0.40;             -- [m] top frame
  constant x_obstacle  : real := 0.36;             -- [m] obstacle (40 mm below the frame)
  constant k_obstacle  : real := 10.0e3;           -- [N/m] obstacle spring (10 N/mm)
  constant rpm_per_n   : real := 13.0;             -- [rpm/N] speed deficit per N of glass force
  constant edges_rev   : integer := 211;           -- [edges] ECU reverse_mm = 100 mm at 2112 edges/m
  type real_list is array (natural range <>) of real;
  constant pinch_volts : real_list := (9.0, 13.0, 16.0);  -- [V] supply of the pinch runs (5.3.2)

  signal hall_a, hall_b       : std_logic := '0';
  signal supply_code          : std_logic_vector(7 downto 0) := (others => '0');
  signal command              : std_logic_vector(1 downto 0) := "00";
  signal relay_up, relay_down : std_logic;
  signal position_v           : std_logic_vector(31 downto 0);  -- [edges] the ECU's output
  signal estimate_v           : std_logic_vector(15 downto 0);  -- [0.1 N] the ECU's estimate of the load
  signal normalized, pinch    : std_logic;
  signal motor_state          : std_logic_vector(1 downto 0);

  signal volts    : real := 13.0;     -- [V] plant supply
  signal obstacle : boolean := false; -- obstacle present
  signal glass    : real := 0.0;      -- [m] glass position (0 = bottom)
  signal push     : real := 0.0;      -- [N] obstacle force on the glass
  signal done     : boolean := false;
  signal current_code : std_logic_vector(9 downto 0) := (others => 'U');  -- no current sensing (the relay ECU)

  -- Component declaration (not a direct entity instantiation): GHDL then analyses this file in any order
  -- relative to ecu_software.vhd; wrsim follows the declaration to the entity of the same name.
  component ecu_software is
    generic (algorithm : natural := 0; learned_file : string := ""; start_position : integer := 0;
             learned_out : string := "");
    port (
      hall_a, hall_b       : in std_logic;
      supply_code          : in std_logic_vector(7 downto 0);
      current_code         : in std_logic_vector(9 downto 0);
      command              : in std_logic_vector(1 downto 0);
      relay_up, relay_down : out std_logic;
      position             : out std_logic_vector(31 downto 0);
      normalized           : out std_logic;
      pinch                : out std_logic;
      motor_state          : out std_logic_vector(1 downto 0);
      estimate             : out std_logic_vector(15 downto 0));
  end component ecu_software;

  -- [edges] the ECU's position as an integer (read in the same delta cycle as the other outputs)
  impure function position return integer is
  begin
    return to_integer(signed(position_v));
  end function position;
begin
  dut: ecu_software
    generic map (algorithm => algorithm, learned_file => learned_file, start_position => start_position,
                 learned_out => learned_out)
    port map (hall_a => hall_a, hall_b => hall_b, supply_code => supply_code, current_code => current_code,
              command => command, relay_up => relay_up, relay_down => relay_down, position => position_v,
              normalized => normalized, pinch => pinch, motor_state => motor_state, estimate => estimate_v);

  plant: process
    variable n     : real := 0.0;   -- [rpm] armature speed
    variable turns : real := 0.0;   -- [rev] armature angle
    variable x     : real := 0.0;   -- [m] glass position
    variable u_m   : real;          -- [V] motor voltage
    variable load  : real;          -- [rpm] speed deficit of the load
    variable n_ss  : real;          -- [rpm] steady-state speed
    variable f     : real;          -- [N] obstacle force
  begin
    while not done loop
      supply_code <= std_logic_vector(to_unsigned(integer(volts * 10.0), 8));
      if relay_up = '1' and relay_down = '0' then
        u_m := volts;
      elsif relay_up = '0' and relay_down = '1' then
        u_m := -volts;
      else
        u_m := 0.0;
      end if;
      f := 0.0;
      if obstacle and x > x_obstacle then
        f := k_obstacle * (x - x_obstacle);
      end if;
      if u_m > 0.0 then      -- lifting: friction rising along the stroke, obstacle, frame
        load := 900.0 + 800.0 * x + rpm_per_n * f + 1.0e7 * realmax(0.0, x - x_top);
        n_ss := realmax(0.0, rpm_per_v * u_m - load);
      elsif u_m < 0.0 then   -- lowering: gravity helps
        n_ss := realmin(0.0, rpm_per_v * u_m + 600.0);
      else                   -- relays off: braked
        n_ss := 0.0;
      end if;
      n := n + (n_ss - n) * dt_s / tau;
      if x <= 0.0 and n < 0.0 then  -- bottom stop
        n := 0.0;
      end if;
      turns := turns + n / 60.0 * dt_s;
      x := x + n / 60.0 * dt_s * m_per_rev;
      -- Hall sensors: 4 poles, pole 1 from -3/16 rev, B lagging A by 1/8 rev (hall_sensor defaults)
      if integer(floor(4.0 * (turns + 0.1875))) mod 2 = 1 then
        hall_a <= '1';
      else
        hall_a <= '0';
      end if;
      if integer(floor(4.0 * (turns + 0.0625))) mod 2 = 1 then
        hall_b <= '1';
      else
        hall_b <= '0';
      end if;
      glass <= x;
      push <= f;
      wait for dt;
    end loop;
    wait;
  end process plant;

  stimulus: process
    variable stroke  : integer;   -- [edges] counted in the normalization run
    variable peak    : real;      -- [N] peak obstacle force of a pinch run
    variable at      : real;      -- [m] glass position at the detection
    variable p_pinch : integer;   -- [edges] position at the detection
    variable estimated : integer; -- [0.1 N] the ECU's estimate at the detection
    variable lowest  : integer;   -- [edges] most negative position of the normalization run

    -- The bits of a command as text (VHDL-2008's to_string is not VHDL-93, which 1076.1 tools analyse).
    function image(c : std_logic_vector(1 downto 0)) return string is
      variable s : string(1 to 2);
    begin
      for k in 1 downto 0 loop
        if c(k) = '1' then
          s(2 - k) := '1';
        else
          s(2 - k) := '0';
        end if;
      end loop;
      return s;
    end function image;

    -- Drive with command c at supply v until the ECU switches the motor off, then release the switch.
    procedure run(c : std_logic_vector(1 downto 0); v : real) is
    begin
      volts <= v;
      command <= c;
      wait until motor_state /= "00" for 10 ms;
      assert motor_state = c report "motor did not start with command " & image(c) severity error;
      wait until motor_state = "00" for 20 sec;
      assert motor_state = "00" report "motor did not stop (command " & image(c) & ")" severity error;
      command <= "00";
      wait for 100 ms;
    end procedure run;
  begin
    wait for 1 us;
    if learned_file'length > 0 then
      -- 5. warm start: normalized at start_position from time 0; on to the pinch runs
      assert normalized = '1' and position = start_position report "no warm start at power-on" severity error;
      report "warm start: position " & integer'image(position);
    else
      -- 1. normalization
      assert normalized = '0' and position = 0 report "not reset at power-on" severity error;
      volts <= 13.0;
      command <= "01";
      lowest := 0;
      while normalized /= '1' and now < 10 sec loop
        wait on position_v, normalized for 10 sec;
        if normalized = '0' and position < lowest then
          lowest := position;
        end if;
      end loop;
      assert normalized = '1' report "normalization did not happen" severity error;
      assert position = 0 report "position after normalization " & integer'image(position) severity error;
      stroke := -lowest;
      report "normalization: stroke " & integer'image(stroke) & " edges, glass at "
             & real'image(glass) & " m";
      assert stroke > 800 and stroke < 900 report "normalization count " & integer'image(lowest)
        severity error;
      wait for 10 ms;
      assert motor_state = "00" report "motor still on after normalization" severity error;
      command <= "00";
      wait for 100 ms;

      -- 2. down to the bottom
      run("10", 13.0);
      report "bottom: position " & integer'image(position);
      assert abs(position - stroke) <= 2 report "bottom position " & integer'image(position)
        & " /= stroke " & integer'image(stroke) severity error;

      -- 3. free run up at 16 V
      volts <= 16.0;
      command <= "01";
      wait until motor_state = "00" for 20 sec;
      assert pinch = '0' report "false pinch at 16 V without obstacle, position " & integer'image(position)
        severity error;
      assert abs(position) <= 3 report "free run ended at " & integer'image(position) severity error;
      report "free run at 16 V: top at position " & integer'image(position);
      command <= "00";
      wait for 100 ms;
    end if;

    -- 4. pinch at 9, 13, 16 V
    for k in 0 to 2 loop
      run("10", 13.0);
      obstacle <= true;
      volts <= pinch_volts(k);
      command <= "01";
      peak := 0.0;
      wait until pinch = '1' or motor_state = "00" for 20 sec;
      assert pinch = '1' report "no pinch detected at " & real'image(volts) & " V" severity error;
      p_pinch := position;
      at := glass;
      estimated := to_integer(signed(estimate_v));
      assert motor_state = "10" report "no reversal after the pinch" severity error;
      while motor_state /= "00" and now < 200 sec loop
        wait on push, motor_state;
        peak := realmax(peak, push);
      end loop;
      report "pinch at " & real'image(volts) & " V: detected at position " & integer'image(p_pinch)
             & " (glass " & real'image(at) & " m, estimate " & integer'image(estimated) & " dN), peak force "
             & real'image(peak) & " N, stopped " & integer'image(position - p_pinch) & " edges lower";
      assert estimated > 0 report "no load estimate at the detection" severity error;
      assert peak < 100.0 report "peak force " & real'image(peak) & " N >= 100 N" severity error;
      assert at > x_obstacle and at < x_obstacle + 0.008
        report "pinch detected at glass " & real'image(at) & " m" severity error;
      assert abs(position - p_pinch - edges_rev) <= 4
        report "reversal of " & integer'image(position - p_pinch) & " edges" severity error;
      assert pinch = '1' report "pinch flag cleared before the next start" severity error;
      command <= "00";
      obstacle <= false;
      wait for 100 ms;
    end loop;

    report "tb_ecu_software_unit: all checks passed";
    done <= true;   -- the plant stops, the ECU waits for an edge or a command: the simulation ends
    wait;
  end process stimulus;
end architecture bench;
