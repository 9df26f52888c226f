library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;
use work.wr_params.all;

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
--   output           = k mod 2                      (4*turns is even)
-- and the same for sensor B at the magnet angle x - phase_shift. Being memoryless, the model is right in
-- both directions and on every reversal by construction (the requirement of 4.3.2). The one difference
-- from the thesis's state machine is its start: the thesis sets the thresholds to 2*pi*s_1 and -2*pi*s_4
-- at angle 0, so its first interval spans the end of pole 4 and pole 1 and the boundary between them is
-- only seen from the second crossing on; here every boundary is active from the start, and pole_offset
-- places angle 0 inside a pole (default: both sensors 1/16 revolution away from the nearest boundary).
--
-- The output is written as the sign of side_a: the angle to the nearest pole boundary, positive over the
-- poles with output 1 and negative over the others (a continuous triangle wave of the angle, 0 on every
-- boundary). hall_a <= '1' when side_a'above(0.0): the edge is exactly the boundary, and as side_a runs
-- smoothly into its zero, the runner places a time point at the crossing (exact 'above crossings,
-- docs/vhdl-ams-subset.md), so the edge is timed to within 1 us whatever ngspice's step. (An earlier 0/1
-- level quantity with a steep ramp at each boundary gave the step control nothing to predict.) The
-- thresholds have no digital consumer and stay true steps (Fig. 4.74).
--
-- Direction: "rotation direction is simply a differentiation of armature angle" (4.3.2):
--   direction = '1' while speed > 0 (positive rotation = lifting, wr_common), '0' otherwise
--   (also at standstill). The ECU can derive the same from the phase between hall_a and hall_b: for
--   positive rotation sensor B lags sensor A by phase_shift, so at an edge of A the new A differs from B.
--
-- Digital outputs (A->D form of the contract): hall_a <= '1' when side_a'above(0.0) else '0'.
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
    pole_shares : real_vector := hall_sensor_pole_shares;   -- [1] shares of the 4 poles in one revolution
    pole_offset : angle       := hall_sensor_pole_offset;   -- armature angle where pole 1 begins (-3*pi/8)
    phase_shift : angle       := hall_sensor_phase_shift);  -- angle by which sensor B lags A (pi/4)
  port (
    terminal shaft        : rotational_v; -- armature shaft
    signal hall_a, hall_b : out std_logic;  -- Hall signals of sensor A and B
    signal direction      : out std_logic); -- '1' while the armature turns positive (lifting)
end entity hall_sensor;

architecture behavioral of hall_sensor is
  quantity speed across shaft;          -- [rad/s] armature speed against the housing
  quantity angle : real;                -- [rad] armature angle against the housing
  quantity side_a : real;               -- [rad] angle to the nearest pole boundary at sensor A, > 0: output 1
  quantity side_b : real;               -- [rad] the same at sensor B
  quantity threshold_bottom : real;     -- [rad] dynamic bottom threshold of sensor A (Fig. 4.74)
  quantity threshold_top    : real;     -- [rad] dynamic top threshold of sensor A (Fig. 4.74)

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

  -- Signed angle [rad] from the magnet angle x [rad] to the nearest pole boundary: > 0 over poles 2 and 4
  -- (output 1), < 0 over poles 1 and 3, 0 on a boundary; continuous, also where floor() jumps (a boundary).
  function pole_side(x : real; shares : real_vector) return real is
    variable frac  : real;
    variable bound : real;
    variable sgn   : real;
    variable side  : real;
  begin
    frac := x / math_2_pi - floor(x / math_2_pi);
    bound := 0.0;
    sgn := -1.0;
    side := 0.0;
    for k in shares'range loop
      if frac >= bound and frac < bound + shares(k) then
        side := sgn * math_2_pi * realmin(frac - bound, bound + shares(k) - frac);
      end if;
      bound := bound + shares(k);
      sgn := -sgn;
    end loop;
    return side;
  end function pole_side;
begin
  assert pole_shares'length = 4 report "hall_sensor: pole_shares needs 4 values (4-pole ring magnet)"
    severity failure;
  assert min_share(pole_shares) > 0.0 report "hall_sensor: pole_shares must be > 0" severity failure;
  assert abs(share_sum(pole_shares) - 1.0) <= 1.0e-9
    report "hall_sensor: pole_shares must sum to 1 (within 1e-9)" severity failure;
  assert phase_shift > 0.0 and phase_shift < math_2_pi * min_share(pole_shares)
    report "hall_sensor: phase_shift must be in (0, 2*pi*min(pole_shares)) rad" severity failure;

  side_a == pole_side(angle - pole_offset, pole_shares);
  side_b == pole_side(angle - pole_offset - phase_shift, pole_shares);
  threshold_bottom == pole_offset + math_2_pi * (turns(angle - pole_offset)
                                                 + pole_start(angle - pole_offset, pole_shares));
  threshold_top == pole_offset + math_2_pi * (turns(angle - pole_offset)
                                              + pole_end(angle - pole_offset, pole_shares));
  angle == speed'integ;

  hall_a <= '1' when side_a'above(0.0) else '0';
  hall_b <= '1' when side_b'above(0.0) else '0';
  direction <= '1' when speed'above(0.0) else '0';
end architecture behavioral;
