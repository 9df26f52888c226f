library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;

-- hall_sensor: two Hall sensors on the 4-pole ring magnet of the motor armature, the drive-speed
-- measurement system of the window regulator (thesis 4.3.2, Fig. 4.72-4.74; packed next to the drive in
-- the system bench, 5.1). Input: the armature angle (no torque is taken from the shaft). Outputs: the two
-- digitised Hall signals and the direction of rotation, as signals for the digital ECU (mixed-signal
-- contract, docs/vhdl-ams-subset.md).
--
-- Ring magnet: four poles with the angular shares s_1 .. s_4 of a revolution (pole_shares, "a sequence of
-- four numbers which have little deviation from 0.25", from the supplier's test report). Pole k of the
-- magnet covers the magnet angles 2*pi*[S_(k-1), S_k) with the cumulative shares S_0 = 0, S_k = s_1 + ..
-- + s_k, S_4 = 1. A sensor's output is 0 over poles 1 and 3 and 1 over poles 2 and 4: it alters at every
-- pole boundary, four times per revolution ("changes four times and gives two pulses").
--
-- Dynamic thresholds (thesis 4.3.2, Fig. 4.74): the thesis keeps a bottom and a top angle threshold
-- around the armature angle; when the angle crosses the top threshold the output alters, the bottom takes
-- the old top and the top moves on by 2*pi*(next share); crossing the bottom shifts them back. Both
-- thresholds are therefore always the two pole boundaries that enclose the current angle -- the boundary
-- at or below it and the next one above it -- and the output is the parity of the pole between them.
-- That is a function of the angle alone, so this model writes it without memory:
--   x      = angle - pole_offset                    magnet angle seen by sensor A [rad]
--   turns  = floor(x/(2*pi)),  frac = x/(2*pi) - turns  in [0, 1)
--   k      = number of S_1, S_2, S_3 with S_j <= frac   (the pole is k + 1)
--   threshold_bottom = pole_offset + 2*pi*(turns + S_k)
--   threshold_top    = pole_offset + 2*pi*(turns + S_(k+1))
--   level_a          = k mod 2                      (0/1 quantity; 4*turns is even)
-- and the same for sensor B at the magnet angle x - phase_shift. Being memoryless, the model is right in
-- both directions and on every reversal by construction (the requirement of 4.3.2). The one difference
-- from the thesis's state machine is its start: the thesis sets the thresholds to 2*pi*s_1 and -2*pi*s_4
-- at angle 0, so its first interval spans the end of pole 4 and pole 1 and the boundary between them is
-- only seen from the second crossing on; here every boundary is active from the start, and pole_offset
-- places angle 0 inside a pole (default: both sensors 1/16 revolution away from the nearest boundary).
--
-- The 0/1 level is written with a linear ramp of edge_width = 1e-5 revolution (63 urad) centred on each
-- boundary, so the 0.5 crossing that switches hall_a is exactly the boundary. With a true step, Newton
-- iterates that straddle a boundary flip the level and with it the adc_bridge, and ngspice ends with
-- "timestep too small" (seen about 1 s into a driven stroke); at working speed the ramp is passed in well
-- under a microsecond. The thresholds have no digital consumer and stay true steps (Fig. 4.74).
--
-- Direction: "rotation direction is simply a differentiation of armature angle" (4.3.2):
--   direction = '1' while speed > 0 (positive rotation = lifting, wr_common), '0' otherwise
--   (also at standstill). The ECU can derive the same from the phase between hall_a and hall_b: for
--   positive rotation sensor B lags sensor A by phase_shift, so at an edge of A the new A differs from B.
--
-- Digital outputs (A->D form of the contract): hall_a <= '1' when level_a'above(0.5) else '0'; edges are
-- placed at ngspice time points, i.e. late by up to one time step: benches that time Hall edges (speed,
-- anti-pinch) bound max_step and say so.
--
-- Sign convention (passive, IEEE 1076.1.1, rotational_v): speed = armature speed against the housing
-- [rad/s], the across quantity of the shaft; the sensor has no through quantity (it takes no torque). The
-- armature angle is the integral of that speed from 0 at t = 0 (the magnet position at the start is set by
-- pole_offset).
--
-- Generics: pole_shares (four shares > 0, sum 1), pole_offset (armature angle at which pole 1 begins at
-- sensor A), phase_shift (mechanical angle by which sensor B lags sensor A; pi/4 = a quarter of the
-- signal period of a 4-pole magnet, i.e. quadrature).
-- Limits: no hysteresis, no chip delay, no supply lines (5.1: omitted), no disturbance from brush
-- commutation (Fig. 4.73); 0 < phase_shift < 2*pi*min(share) keeps A and B edges apart.
entity hall_sensor is
  generic (
    pole_shares : real_vector := (0.25, 0.25, 0.25, 0.25);  -- [1] shares of the 4 poles in one revolution
    pole_offset : angle := -1.1780972450961724;              -- armature angle where pole 1 begins (-3*pi/8)
    phase_shift : angle := 0.7853981633974483);              -- angle by which sensor B lags A (pi/4)
  port (
    terminal shaft        : rotational_v; -- armature shaft
    signal hall_a, hall_b : out std_logic;  -- Hall signals of sensor A and B
    signal direction      : out std_logic); -- '1' while the armature turns positive (lifting)
end entity hall_sensor;

architecture behavioral of hall_sensor is
  quantity speed across shaft;          -- [rad/s] armature speed against the housing
  quantity angle : real;                -- [rad] armature angle against the housing
  quantity level_a : real;              -- [1] output of sensor A as 0/1
  quantity level_b : real;              -- [1] output of sensor B as 0/1
  quantity threshold_bottom : real;     -- [rad] dynamic bottom threshold of sensor A (Fig. 4.74)
  quantity threshold_top    : real;     -- [rad] dynamic top threshold of sensor A (Fig. 4.74)
  constant edge_width : real := 1.0e-5; -- [1] width of the output ramp at a pole boundary, in revolutions

  -- Smallest pole share (generic check).
  function min_share(shares : real_vector) return real is
    variable m : real;
  begin
    m := real'high;
    for k in shares'range loop
      m := realmin(m, shares(k));
    end loop;
    return m;
  end function min_share;

  -- Sum of the pole shares (generic check).
  function share_sum(shares : real_vector) return real is
    variable s : real;
  begin
    s := 0.0;
    for k in shares'range loop
      s := s + shares(k);
    end loop;
    return s;
  end function share_sum;

  -- Whole revolutions of the magnet angle x [rad]: floor(x/(2*pi)).
  function turns(x : real) return real is
  begin
    return floor(x / math_2_pi);
  end function turns;

  -- Cumulative share S_k at the start of the pole that holds the magnet angle x [rad] (0 for pole 1).
  function pole_start(x : real; shares : real_vector) return real is
    variable frac  : real;
    variable bound : real;
    variable start : real;
  begin
    frac := x / math_2_pi - floor(x / math_2_pi);
    bound := 0.0;
    start := 0.0;
    for k in shares'low to shares'high - 1 loop
      bound := bound + shares(k);
      if frac >= bound then
        start := bound;
      end if;
    end loop;
    return start;
  end function pole_start;

  -- Cumulative share S_(k+1) at the end of the pole that holds the magnet angle x [rad] (1 for pole 4).
  function pole_end(x : real; shares : real_vector) return real is
    variable frac  : real;
    variable bound : real;
    variable stop  : real;
  begin
    frac := x / math_2_pi - floor(x / math_2_pi);
    bound := 0.0;
    stop := 1.0;
    for k in shares'low to shares'high - 1 loop
      if frac >= bound and frac < bound + shares(k) then
        stop := bound + shares(k);
      end if;
      bound := bound + shares(k);
    end loop;
    return stop;
  end function pole_end;

  -- Sensor output 0/1 at the magnet angle x [rad]: the parity of the pole index (poles 2 and 4 give 1),
  -- written continuously: every boundary is a linear ramp of edge_width revolutions centred on it, and
  -- the revolution is counted from the middle of pole 1 (g), so that the jump of floor() falls where the
  -- output is 0 on both sides.
  function pole_level(x : real; shares : real_vector) return real is
    variable g     : real;
    variable bound : real;
    variable sgn   : real;
    variable level : real;
  begin
    g := x / math_2_pi - 0.5 * shares(shares'low);
    g := g - floor(g);
    bound := -0.5 * shares(shares'low);
    sgn := 1.0;
    level := 0.0;
    for k in shares'range loop
      bound := bound + shares(k);
      level := level + sgn * realmin(1.0, realmax(0.0, (g - bound) / edge_width + 0.5));
      sgn := -sgn;
    end loop;
    return level;
  end function pole_level;
begin
  assert pole_shares'length = 4 report "hall_sensor: pole_shares needs 4 values (4-pole ring magnet)"
    severity failure;
  assert min_share(pole_shares) > 0.0 report "hall_sensor: pole_shares must be > 0" severity failure;
  assert abs(share_sum(pole_shares) - 1.0) <= 1.0e-9
    report "hall_sensor: pole_shares must sum to 1 (within 1e-9)" severity failure;
  assert phase_shift > 0.0 and phase_shift < math_2_pi * min_share(pole_shares)
    report "hall_sensor: phase_shift must be in (0, 2*pi*min(pole_shares)) rad" severity failure;

  level_a == pole_level(angle - pole_offset, pole_shares);
  level_b == pole_level(angle - pole_offset - phase_shift, pole_shares);
  threshold_bottom == pole_offset + math_2_pi * (turns(angle - pole_offset)
                                                 + pole_start(angle - pole_offset, pole_shares));
  threshold_top == pole_offset + math_2_pi * (turns(angle - pole_offset)
                                              + pole_end(angle - pole_offset, pole_shares));
  angle == speed'integ;

  hall_a <= '1' when level_a'above(0.5) else '0';
  hall_b <= '1' when level_b'above(0.5) else '0';
  direction <= '1' when speed'above(0.0) else '0';
end architecture behavioral;
