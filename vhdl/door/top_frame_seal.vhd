library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;
use work.wr_params.all;

-- top_frame_seal: the sealing of the upper door frame and the metal frame behind it (thesis 4.3.1.1,
-- Fig. 4.70/4.71). The glass intrudes into the top sealing by 20 .. 40 mm; the intrusion is divided into
-- three ranges, each with its own friction and stiffness (outer branches first, then inner ones: both rise
-- from range to range); behind the last range the metal frame stops the glass as a spring of mega-N/m order.
--
-- Equations (velocity form; pos = position0 + integral of v dt, d = pos - position = intrusion of the glass
-- edge into the sealing):
--   elastic force  F_e(d) = sum over the ranges k of stiffness_k*(length of range k already compressed)
--                           + frame_stiffness*(d - total length) once the metal frame is reached
--                  (continuous, piecewise linear, stiffness rising from range to range)
--   friction       F_r(d) = friction_k in range k (the last range's value on the metal frame), 0 for d <= 0,
--                  directed against the velocity: smooth_sign(v, v_threshold) as seal_friction (4.3.1.1)
--   force == elastic(intrusion) + friction(intrusion) * smooth_sign(v, v_threshold)
--
-- Sign convention (passive, IEEE 1076.1.1, translational_v): v = glass velocity against the door frame
-- [m/s] (positive up); force = force the sealing and frame take from the glass [N] (> 0: they push the
-- glass down).
--
-- Generics: position (glass position at which its edge touches the sealing), lengths, frictions, stiffnesses
-- (three values each, per range, user-settable as in the thesis; identified from the slope changes of the
-- drum torque over angle, Fig. 4.71), frame_stiffness, v_threshold, position0 (glass position at t = 0).
-- Limits: no hysteresis of the rubber, no glass geometry (the edge meets the sealing at one position).
entity top_frame_seal is
  generic (
    position        : displacement := top_frame_seal_position;         -- glass position where the sealing begins
    lengths         : real_vector  := top_frame_seal_lengths;          -- [m] lengths of the three intrusion ranges
    frictions       : real_vector  := top_frame_seal_frictions;        -- [N] friction force in each range
    stiffnesses     : real_vector  := top_frame_seal_stiffnesses;      -- [N/m] sealing stiffness in each range
    frame_stiffness : stiffness    := top_frame_seal_frame_stiffness;  -- stiffness of the metal door frame
    v_threshold     : velocity     := top_frame_seal_v_threshold;      -- speed below which sgn(v) is linear
    position0       : displacement := top_frame_seal_position0);       -- glass position at t = 0
  port (
    terminal glass, frame : translational_v);  -- glass edge, door frame (usually the reference)
end entity top_frame_seal;

architecture behavioral of top_frame_seal is
  quantity v across force through glass to frame;  -- glass velocity [m/s], force [N] taken from the glass
  quantity pos       : displacement;  -- glass position
  quantity intrusion : displacement;  -- intrusion of the glass edge into the sealing (< 0: no contact)

  -- Elastic force of the ranges and the frame at intrusion d (continuous, piecewise linear).
  function elastic(d : real; ls : real_vector; ks : real_vector; k_frame : real) return real is
    variable f     : real := 0.0;
    variable start : real := 0.0;
  begin
    for k in ls'range loop
      f := f + ks(k) * realmin(ls(k), realmax(0.0, d - start));
      start := start + ls(k);
    end loop;
    return f + k_frame * realmax(0.0, d - start);
  end function elastic;

  -- Friction magnitude at intrusion d: the value of the range d lies in (the last range's beyond it).
  function friction(d : real; ls : real_vector; fs : real_vector) return real is
    variable f     : real := 0.0;
    variable start : real := 0.0;
  begin
    for k in ls'range loop
      if d > start then
        f := fs(k);
      end if;
      start := start + ls(k);
    end loop;
    return f;
  end function friction;

  -- Smallest entry of a vector.
  function smallest(xs : real_vector) return real is
    variable m : real := real'high;
  begin
    for k in xs'range loop
      m := realmin(m, xs(k));
    end loop;
    return m;
  end function smallest;
begin
  assert lengths'length = 3 and frictions'length = 3 and stiffnesses'length = 3
    report "top_frame_seal: lengths, frictions and stiffnesses need 3 values each (three ranges)" severity failure;
  assert smallest(lengths) > 0.0 report "top_frame_seal: lengths must be > 0" severity failure;
  assert smallest(frictions) >= 0.0 report "top_frame_seal: frictions must be >= 0" severity failure;
  assert smallest(stiffnesses) > 0.0 report "top_frame_seal: stiffnesses must be > 0" severity failure;
  assert frame_stiffness > 0.0 report "top_frame_seal: frame_stiffness must be > 0" severity failure;
  assert v_threshold > 0.0 and v_threshold <= 1.0e-3
    report "top_frame_seal: v_threshold must be in (0, 1e-3] m/s" severity failure;

  pos == position0 + v'integ;
  intrusion == pos - position;
  force == elastic(intrusion, lengths, stiffnesses, frame_stiffness)
           + friction(intrusion, lengths, frictions) * smooth_sign(v, v_threshold);
end architecture behavioral;
