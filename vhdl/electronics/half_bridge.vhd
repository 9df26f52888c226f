library IEEE;
use IEEE.MATH_REAL.all;
use work.wr_common.all;

-- half_bridge: the laws of one leg of a MOSFET bridge (h_bridge): a high-side and a low-side MOSFET with their body
-- diodes between the battery and one motor terminal. Both of h_bridge's architectures write their legs with them, so
-- that the averaged and the switched bridge differ only in the shares of a period each MOSFET conducts:
--   a_h (high side on), a_l (low side on), a_d = 1 - a_h - a_l (both off: a body diode carries the current)
-- averaged over a PWM period (share_high, share_low) or 0/1 at each instant (h_bridge(switched)).
-- Leg voltage against the battery's minus, with i the current out of the leg into the motor (h_bridge's header):
--   v_leg = a_h*(u - r*i) - a_l*r*i + a_d*(p*(-(v_f + r_f*i)) + (1 - p)*(u + v_f - r_f*i))
--   i_bat = a_h*i + a_d*(1 - p)*i          (what the leg takes from the battery's plus; < 0: into it)
--   p     = (1 + smooth_sign(i, band))/2   (the low diode's share: 1 for i > band, 0 for i < -band)
package half_bridge is
  -- The shares of a period the high and the low side of a switching leg are on at duty x with the dead time td (a
  -- share of the period): max(0, x - td) and max(0, 1 - x - td); duty 1 and 0 do not switch.
  function share_high(x, td : real) return real;
  function share_low(x, td : real) return real;

  -- The high and low side's share of a leg in bridge mode m (1 drive, 2 freewheel, 3 brake, other: off); switching:
  -- the leg of the direction (it switches at gh, gl while driving and is off while freewheeling; the other leg's
  -- low side is on; braking, both low sides are on).
  function leg_high(m : integer; switching : boolean; gh : real) return real;
  function leg_low(m : integer; switching : boolean; gl : real) return real;

  -- The leg's voltage and battery current (header).
  function leg_v(ah, al, u, i, r, vf, rf, band : real) return real;
  function leg_i(ah, al, i, band : real) return real;
end package half_bridge;

package body half_bridge is
  function share_high(x, td : real) return real is
  begin
    if x >= 1.0 then
      return 1.0;
    end if;
    return realmax(0.0, x - td);
  end function share_high;

  function share_low(x, td : real) return real is
  begin
    if x <= 0.0 then
      return 1.0;
    end if;
    return realmax(0.0, 1.0 - x - td);
  end function share_low;

  function leg_high(m : integer; switching : boolean; gh : real) return real is
  begin
    if m = 1 and switching then
      return gh;
    end if;
    return 0.0;
  end function leg_high;

  function leg_low(m : integer; switching : boolean; gl : real) return real is
  begin
    if m = 1 and switching then
      return gl;
    elsif m = 1 or m = 3 or (m = 2 and not switching) then
      return 1.0;
    end if;
    return 0.0;
  end function leg_low;

  function leg_v(ah, al, u, i, r, vf, rf, band : real) return real is
    variable p : real;
  begin
    p := 0.5 + 0.5 * smooth_sign(i, band);
    return ah * (u - r * i) - al * r * i + (1.0 - ah - al) * (p * (-(vf + rf * i)) + (1.0 - p) * (u + vf - rf * i));
  end function leg_v;

  function leg_i(ah, al, i, band : real) return real is
  begin
    return ah * i + (1.0 - ah - al) * (0.5 - 0.5 * smooth_sign(i, band)) * i;
  end function leg_i;
end package body half_bridge;
