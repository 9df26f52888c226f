library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;
use work.wr_common.all;
use work.wr_params.all;

-- ecu_sense: what the semiconductor ECU measures for its software (motor_controller): the motor current through a
-- shunt in the motor lead between the H-bridge (h_bridge) and the motor, a bidirectional current-sense amplifier with
-- its output at mid-supply for zero current (the usual in-line, PWM-rejecting sense amplifier), and the supply
-- voltage at the ECU's battery terminals; the microcontroller's ADC samples both at the PWM's instants and delivers
-- the last conversions as current_code (10 bits) and supply_code (8 bits, the relay ECU's format, ecu_hardware).
--   shunt:     u == r_shunt*i                                   (i from p through the shunt to n, into the motor)
--   amplifier: v_amp = clip(v_mid + gain*r_shunt*i, 0, v_adc)   [V]
--   ADC:       code  = clip(floor(v_amp/v_adc*1024), 0, 1023)
--   software:  i ~ (code - 512 + 0.5)*v_adc/(1024*gain*r_shunt)   (0.0488 A per step with the defaults)
--   supply:    supply_code = clip(floor(u_supply/0.1 V + 0.5), 0, 255)   [0.1 V]
-- Sampling: the ADC converts at every PWM period (20 kHz), triggered at the centre of an on-phase, where the motor
-- current equals its mean over the period; the averaged h_bridge delivers that mean, and nothing it does changes
-- within a period, so the codes here are the quantized averaged current and supply, and change where these cross a
-- step (an A->D edge each, located on its crossing). The software reads the last conversion when it runs.
-- Each bit is a 0/1 quantity and reaches the software through one A->D assignment (as ecu_hardware's supply code).
-- Sign convention (passive, IEEE 1076.1.1): u = v(p) - v(n), i the current from p through the shunt to n;
-- u_supply = v(bat_p) - v(bat_n) (no current taken).
-- Generics: r_shunt, gain, v_adc (the ADC's reference; the amplifier's output range 0 .. v_adc, zero current at
-- v_adc/2). Defaults: a 1 mOhm shunt and a gain of 100 V/V (INA240A4-class), a 5 V ADC:
-- +-25 A (the stall current at 16 V and -40 degC, 21 A, inside).
-- Limits: no amplifier bandwidth, offset or noise; an ideal sampler; the amplifier clips at its rails; no ripple
-- (the averaged bridge).
entity ecu_sense is
  generic (
    r_shunt  : resistance := ecu_sense_r_shunt;   -- shunt resistance
    gain     : real       := ecu_sense_gain;      -- [V/V] amplifier gain
    v_adc    : voltage    := ecu_sense_v_adc);    -- ADC reference (full scale)
  port (
    terminal p, n         : electrical;                          -- shunt: bridge side, motor side
    terminal bat_p, bat_n : electrical;                          -- the ECU's battery terminals
    signal current_code   : out std_logic_vector(9 downto 0);   -- [ADC steps] the last current conversion
    signal supply_code    : out std_logic_vector(7 downto 0));  -- [0.1 V] the last supply conversion
end entity ecu_sense;

architecture behavioral of ecu_sense is
  quantity u across i through p to n;  -- [V] shunt voltage, [A] motor current
  quantity v_amp : voltage;            -- amplifier output
  quantity code : real;                -- [1] the ADC's last conversion, 0 .. 1023
  quantity bit0, bit1, bit2, bit3, bit4, bit5, bit6, bit7, bit8, bit9 : real;  -- [1] its bits, 0/1
  quantity u_supply across bat_p to bat_n;  -- [V] supply voltage at the ECU

  quantity s_code : real;                   -- [1] the supply's last conversion, 0 .. 255
  quantity sbit0, sbit1, sbit2, sbit3, sbit4, sbit5, sbit6, sbit7 : real;  -- [1] its bits, 0/1
begin
  assert r_shunt > 0.0 and gain > 0.0 and v_adc > 0.0
    report "ecu_sense: r_shunt, gain and v_adc must be > 0" severity failure;

  u == r_shunt * i;
  v_amp == realmin(v_adc, realmax(0.0, 0.5 * v_adc + gain * r_shunt * i));
  code == realmin(1023.0, realmax(0.0, floor(v_amp / v_adc * 1024.0)));
  bit0 == bit_of(code, 0);
  bit1 == bit_of(code, 1);
  bit2 == bit_of(code, 2);
  bit3 == bit_of(code, 3);
  bit4 == bit_of(code, 4);
  bit5 == bit_of(code, 5);
  bit6 == bit_of(code, 6);
  bit7 == bit_of(code, 7);
  bit8 == bit_of(code, 8);
  bit9 == bit_of(code, 9);

  current_code(0) <= '1' when bit0'above(0.5) else '0';
  current_code(1) <= '1' when bit1'above(0.5) else '0';
  current_code(2) <= '1' when bit2'above(0.5) else '0';
  current_code(3) <= '1' when bit3'above(0.5) else '0';
  current_code(4) <= '1' when bit4'above(0.5) else '0';
  current_code(5) <= '1' when bit5'above(0.5) else '0';
  current_code(6) <= '1' when bit6'above(0.5) else '0';
  current_code(7) <= '1' when bit7'above(0.5) else '0';
  current_code(8) <= '1' when bit8'above(0.5) else '0';
  current_code(9) <= '1' when bit9'above(0.5) else '0';


  s_code == realmin(255.0, realmax(0.0, floor(u_supply / 0.1 + 0.5)));
  sbit0 == bit_of(s_code, 0);
  sbit1 == bit_of(s_code, 1);
  sbit2 == bit_of(s_code, 2);
  sbit3 == bit_of(s_code, 3);
  sbit4 == bit_of(s_code, 4);
  sbit5 == bit_of(s_code, 5);
  sbit6 == bit_of(s_code, 6);
  sbit7 == bit_of(s_code, 7);
  supply_code(0) <= '1' when sbit0'above(0.5) else '0';
  supply_code(1) <= '1' when sbit1'above(0.5) else '0';
  supply_code(2) <= '1' when sbit2'above(0.5) else '0';
  supply_code(3) <= '1' when sbit3'above(0.5) else '0';
  supply_code(4) <= '1' when sbit4'above(0.5) else '0';
  supply_code(5) <= '1' when sbit5'above(0.5) else '0';
  supply_code(6) <= '1' when sbit6'above(0.5) else '0';
  supply_code(7) <= '1' when sbit7'above(0.5) else '0';
end architecture behavioral;
