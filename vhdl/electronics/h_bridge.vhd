library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;
use IEEE.NUMERIC_STD.all;
use work.half_bridge.all;
use work.wr_params.all;

-- h_bridge: the power stage of a semiconductor window-lift ECU, a MOSFET full bridge driven with PWM (the
-- successor of the thesis's relay pair, ecu_hardware; thesis 4.3.3.1 describes only the relays). Two legs, one per
-- motor terminal: leg A on mot_p, leg B on mot_n, each a high-side and a low-side MOSFET with its body diode.
-- The ECU software (motor_controller) sets the duty, the mode and the direction:
--   mode "01" drive:     the leg of the direction switches at f_pwm (high side on for the duty, low side on for
--                        the rest: synchronous rectification), the other leg's low side is on. dir = '1': leg A
--                        switches, the motor voltage is positive (the glass goes up); dir = '0': leg B switches.
--   mode "10" freewheel: the switching leg is off, the other leg's low side on: the motor current decays through
--                        that MOSFET and the off leg's body diode, and stops at zero (the diode blocks).
--   mode "11" brake:     both low sides on: the motor short-circuited through 2*r_ds_on (active braking).
--   mode "00" off:       all four off: a current decays through two body diodes back into the battery (fast decay).
-- Dead time: each MOSFET turns on dead_time after its partner turns off; while both of a switching leg are off its
-- body diodes carry the current (the low one for a current out of the leg, the high one for a current into it).
-- Duty 0 and 1 do not switch (no dead time); a duty the dead time swallows leaves that switch off.
--
-- Leg voltage against bat_n, with i the current out of the leg into the motor and the shares of a period
-- a_h (high side on), a_l (low side on), a_d = 1 - a_h - a_l (dead time, a body diode on):
--   switching leg, duty d, t_d = dead_time*f_pwm: a_h = max(0, d - t_d), a_l = max(0, 1 - d - t_d)
--   (d = 0: a_l = 1; d = 1: a_h = 1); low side on: a_l = 1; off: a_h = a_l = 0
--   v_leg = a_h*(u - r*i) - a_l*r*i + a_d*(p*(-(v_f + r_f*i)) + (1 - p)*(u + v_f - r_f*i))
--   i_leg = a_h*i + a_d*(1 - p)*i            (the current it takes from bat_p; < 0: into the battery)
--   p     = (1 + smooth_sign(i, i_band))/2   (the low diode's share: 1 for i > i_band, 0 for i < -i_band)
-- The architecture `averaged` writes these means over a period (state-space averaging: valid while the motor's
-- electrical time constant laa/ra is long against 1/f_pwm, here 0.1 ms against 50 us); `switched` switches each
-- MOSFET at its instants (a check of the averaging, tests/unit/test_h_bridge.py). The i_band smoothing stands
-- for the instant of a diode's turn-off: below i_band an off leg is a steep resistance (u + 2*v_f)/(2*i_band)
-- instead of an open circuit.
-- r_ds_on is at the junction's temperature: a parameter set's [ambient] temperature scales the value the set gives
-- (wrsim.data.temperature, +0.5 %/K, datasheet curves of automotive trench MOSFETs; no self-heating).
--
-- Sign convention (passive, IEEE 1076.1.1): u_bat = v(bat_p) - v(bat_n), i_bat the current the bridge takes at
-- bat_p (> 0 while it drives); v_a = v(mot_p) - v(bat_n), v_b = v(mot_n) - v(bat_n), u_m = v_a - v_b, i_m the
-- current out of mot_p through the motor and back into mot_n.
-- Generics: r_ds_on (per MOSFET, on), v_f and r_f (body diode: forward voltage and slope), dead_time, f_pwm,
-- i_band (the diode's smoothing band).
-- Limits: no switching losses, no gate drive, no capacitances, no thermal model (the junction at the set's
-- temperature); the averaged architecture has no ripple; current sensing is current_sense.
entity h_bridge is
  generic (
    r_ds_on   : resistance := h_bridge_r_ds_on;    -- on-resistance of one MOSFET at its junction temperature
    v_f       : voltage    := h_bridge_v_f;        -- body diode forward voltage
    r_f       : resistance := h_bridge_r_f;        -- body diode slope resistance
    dead_time : real       := h_bridge_dead_time;  -- [s] both MOSFETs of a leg off at each switching
    f_pwm     : real       := h_bridge_f_pwm;      -- [Hz] PWM frequency
    i_band    : current    := h_bridge_i_band);    -- current below which a body diode is smoothed off
  port (
    terminal bat_p, bat_n : electrical;                 -- battery plus, minus
    terminal mot_p, mot_n : electrical;                 -- motor plus, minus
    signal duty           : in std_logic_vector(9 downto 0);  -- [1/1023] duty of the switching leg
    signal mode           : in std_logic_vector(1 downto 0);  -- "00" off, "01" drive, "10" freewheel, "11" brake
    signal dir            : in std_logic);                    -- '1': leg A switches (up), '0': leg B (down)
begin
  assert r_ds_on > 0.0 report "h_bridge: r_ds_on must be > 0" severity failure;
  assert v_f >= 0.0 and r_f > 0.0 report "h_bridge: v_f must be >= 0 and r_f > 0" severity failure;
  assert f_pwm > 0.0 report "h_bridge: f_pwm must be > 0" severity failure;
  assert dead_time >= 0.0 and dead_time * f_pwm < 0.1
    report "h_bridge: dead_time must be >= 0 and below a tenth of the PWM period" severity failure;
  assert i_band > 0.0 report "h_bridge: i_band must be > 0" severity failure;
end entity h_bridge;

architecture averaged of h_bridge is
  quantity u_bat across i_bat through bat_p to bat_n;  -- [V], [A] the battery side
  quantity v_a across i_a through mot_p to bat_n;      -- [V] mean voltage of leg A, [A] into it (-i_m)
  quantity v_b across i_b through mot_n to bat_n;      -- [V] mean voltage of leg B, [A] into it (i_m)
  quantity i_m : current;                              -- current out of mot_p through the motor
  quantity u_m : voltage;                              -- motor voltage
  quantity ah_a, al_a, ah_b, al_b : real;              -- [1] shares of a period: high / low side of leg A, B on
  quantity d : real;                                   -- [1] the duty

  constant td : real := dead_time * f_pwm;  -- [1] dead time as a share of the period
begin
  break on duty, mode, dir;  -- the shares step when the software sets them

  d == realmin(1.0, real(to_integer(unsigned(duty))) / 1023.0);
  ah_a == leg_high(to_integer(unsigned(mode)), dir = '1', share_high(d, td));
  al_a == leg_low(to_integer(unsigned(mode)), dir = '1', share_low(d, td));
  ah_b == leg_high(to_integer(unsigned(mode)), dir = '0', share_high(d, td));
  al_b == leg_low(to_integer(unsigned(mode)), dir = '0', share_low(d, td));

  -- each leg's out-current is its branch current reversed; the motor closes the loop (i_b = -i_a = i_m)
  v_a == leg_v(ah_a, al_a, u_bat, -i_a, r_ds_on, v_f, r_f, i_band);
  v_b == leg_v(ah_b, al_b, u_bat, -i_b, r_ds_on, v_f, r_f, i_band);
  i_bat == leg_i(ah_a, al_a, -i_a, i_band) + leg_i(ah_b, al_b, -i_b, i_band);
  i_m == -i_a;
  u_m == v_a - v_b;
end architecture averaged;

-- switched: each MOSFET on or off at its instants, for checking the averaging (tests/unit/test_pwm_ecu.py). The
-- carrier ph rises from 0 to 1 over each PWM period (from the period's start, sampled with 'zoh, which gives the
-- analog solver a time point there); the switching leg's high side
-- is on over ph in [t_d, d), its low side over [d + t_d, 1) (duty 1: the high side throughout, duty 0: the low side).
-- Each gate change is an 'above crossing, located on a time point: some 80,000 per second at 20 kHz.
architecture switched of h_bridge is
  quantity u_bat across i_bat through bat_p to bat_n;  -- [V], [A] the battery side
  quantity v_a across i_a through mot_p to bat_n;      -- [V] voltage of leg A, [A] into it (-i_m)
  quantity v_b across i_b through mot_n to bat_n;      -- [V] voltage of leg B, [A] into it (i_m)
  quantity i_m : current;                              -- current out of mot_p through the motor
  quantity u_m : voltage;                              -- motor voltage
  quantity ah_a, al_a, ah_b, al_b : real;              -- [1] 0/1: high / low side of leg A, B on
  quantity d : real;                                   -- [1] the duty
  quantity t_now : real;                               -- [s] the time
  quantity t_period : real;                            -- [s] the start of the present PWM period
  quantity ph : real;                                  -- [1] the carrier: the share of the period passed
  quantity gh, gl : real;                              -- [1] 0/1: the switching leg's high / low side on

  constant td : real := dead_time * f_pwm;  -- [1] dead time as a share of the period
  signal high_on, low_on : boolean;         -- the switching leg's gates
begin
  t_now == now;
  t_period == t_now'zoh(1.0 / f_pwm);
  ph == f_pwm * (t_now - t_period);

  break on duty, mode, dir;
  d == realmin(1.0, real(to_integer(unsigned(duty))) / 1023.0);
  high_on <= d'above(0.9995) or (ph'above(td) and not ph'above(d));
  low_on <= not d'above(0.0005) or ph'above(d + td);
  if high_on use
    gh == 1.0;
  else
    gh == 0.0;
  end use;
  if low_on and not high_on use
    gl == 1.0;
  else
    gl == 0.0;
  end use;
  ah_a == leg_high(to_integer(unsigned(mode)), dir = '1', gh);
  al_a == leg_low(to_integer(unsigned(mode)), dir = '1', gl);
  ah_b == leg_high(to_integer(unsigned(mode)), dir = '0', gh);
  al_b == leg_low(to_integer(unsigned(mode)), dir = '0', gl);

  v_a == leg_v(ah_a, al_a, u_bat, -i_a, r_ds_on, v_f, r_f, i_band);
  v_b == leg_v(ah_b, al_b, u_bat, -i_b, r_ds_on, v_f, r_f, i_band);
  i_bat == leg_i(ah_a, al_a, -i_a, i_band) + leg_i(ah_b, al_b, -i_b, i_band);
  i_m == -i_a;
  u_m == v_a - v_b;
end architecture switched;
