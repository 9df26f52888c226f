-- wr_common: subtypes, constants and functions shared by every window-regulator model.
-- Compile into library WORK next to the models.
--
-- Port-name conventions (used by every model in vhdl/):
--   electrical pins        p (plus), n (minus)
--   rotational shafts      shaft (a single shaft), shaft_a / shaft_b (two-port elements: springs,
--                          dampers, couplings), worm / gear (the two sides of a worm gear stage)
--   translational pins     glass (glass carrier), cable_a / cable_b (cable ends), frame (door frame)
-- Positive rotation of the drive output lifts the glass (window closing direction).
-- Mechanical nodes are velocity nodes (rotational_v, translational_v: across = speed), never position
-- nodes: a speed that is the derivative of a large angle or position (the armature turns about 1500 rad
-- over a stroke) is lost in rounding at small time steps, which makes a circuit solver fail on shafts at
-- rest in their friction bands. Angles, positions and spring deformations are integrals of the speeds
-- ('integ, or deformation'dot == speed where the DC point must leave the deformation to the static load).
library IEEE;
use IEEE.MATH_REAL.all;

package wr_common is
  -- Unit conversions.
  constant rpm_per_radps : real := 60.0 / math_2_pi;  -- [rpm/(rad/s)]
  constant deg_per_rad   : real := 180.0 / math_pi;   -- [deg/rad]

  -- Default velocity thresholds of the smoothed friction laws (thesis 4.1.2.4: "milli or even micro").
  constant default_omega_threshold : real := 1.0e-3;  -- [rad/s]
  constant default_v_threshold     : real := 1.0e-3;  -- [m/s]

  -- sign(x) made continuous: linear between -threshold and +threshold (thesis 4.1.2.4, 4.3.1.1).
  function smooth_sign(x : real; threshold : real) return real;

  -- Piecewise-linear interpolation of ys over the strictly increasing xs; constant beyond the ends.
  function table_lookup(x : real; xs : real_vector; ys : real_vector) return real;

  -- Bit k (0/1) of the non-negative whole number n (k static): the digitisation of an ADC register, one 0/1
  -- quantity per bit (ecu_hardware, ecu_sense).
  function bit_of(n : real; k : integer) return real;

  -- Checks for table generics (used in `assert ... severity failure` of the models).
  function strictly_increasing(xs : real_vector) return boolean;
  function all_positive(xs : real_vector) return boolean;
  function all_nonnegative(xs : real_vector) return boolean;
end package wr_common;

package body wr_common is
  function smooth_sign(x : real; threshold : real) return real is
  begin
    if x > threshold then
      return 1.0;
    elsif x < -threshold then
      return -1.0;
    else
      return x / threshold;
    end if;
  end function smooth_sign;

  function bit_of(n : real; k : integer) return real is
  begin
    return floor(n / 2.0 ** k) - 2.0 * floor(n / 2.0 ** (k + 1));
  end function bit_of;

  function table_lookup(x : real; xs : real_vector; ys : real_vector) return real is
    variable y : real := ys(ys'low);
  begin
    for k in xs'low + 1 to xs'high loop
      if x > xs(k - 1) then
        if x >= xs(k) then
          y := ys(k);
        else
          y := ys(k - 1) + (ys(k) - ys(k - 1)) * (x - xs(k - 1)) / (xs(k) - xs(k - 1));
        end if;
      end if;
    end loop;
    return y;
  end function table_lookup;

  function strictly_increasing(xs : real_vector) return boolean is
    variable ok : boolean := true;
  begin
    for k in xs'low + 1 to xs'high loop
      if xs(k) <= xs(k - 1) then
        ok := false;
      end if;
    end loop;
    return ok;
  end function strictly_increasing;

  function all_positive(xs : real_vector) return boolean is
    variable ok : boolean := true;
  begin
    for k in xs'low to xs'high loop
      if xs(k) <= 0.0 then
        ok := false;
      end if;
    end loop;
    return ok;
  end function all_positive;

  function all_nonnegative(xs : real_vector) return boolean is
    variable ok : boolean := true;
  begin
    for k in xs'low to xs'high loop
      if xs(k) < 0.0 then
        ok := false;
      end if;
    end loop;
    return ok;
  end function all_nonnegative;
end package body wr_common;
