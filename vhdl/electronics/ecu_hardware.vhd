library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;
use work.wr_common.all;
use work.wr_params.all;

-- ecu_hardware: the analog side of the window-regulator electronics (thesis 4.3.3.1, Fig. 4.76; system
-- bench 5.1 a): the two relays that connect the motor to the battery, and the digitisation of the supply
-- voltage for the software. The software (ecu_software, digital, GHDL) drives the relays through
-- relay_up/relay_down ("two software signals ... control two relays. The combinations of the two
-- controlling signals lead to motor driving glass upwards, downwards or stop") and reads supply_code
-- ("amplitude of voltage is digitalized into register and then passed to software"). Hall signals go from
-- the hall_sensor to the software directly; the time register is the software's own clock.
--
-- H-bridge of two changeover relays, one per motor terminal (the usual window-lift relay pair):
--   relay_up   = '1': mot_p on bat_p (normally-open contact),  '0': mot_p on bat_n (normally closed)
--   relay_down = '1': mot_n on bat_p (normally-open contact),  '0': mot_n on bat_n (normally closed)
--   up   (relay_up = '1', relay_down = '0'): motor voltage +U, the motor lifts the glass;
--   down (relay_up = '0', relay_down = '1'): motor voltage -U;
--   stop (both '0'): both motor terminals on bat_n, i.e. the motor is short-circuited and brakes on its
--        own back-EMF (dynamic braking); both '1' short-circuits it on bat_p, the same brake.
--   The thesis does not describe the stop state beyond "stop"; the short-circuit follows from the
--   changeover relays (and is what the test-stand supply of 4.1.2.6 does when it is "off", pwl_supply).
-- Each contact is a resistance r_contact when closed and an open circuit (no current) when open:
--   closed:  u == r_contact*i        open:  i == 0
-- written as simultaneous if-use statements on the relay signals (mixed-signal contract).
--
-- Supply digitisation (8-bit register, LSB 0.1 V, 0 .. 25.5 V, rounded to the nearest step):
--   code  = clip(floor(u_supply/0.1 V + 0.5), 0, 255)
--   bit_k = floor(code/2**k) - 2*floor(code/2**(k+1))        (0/1 quantity per bit)
--   supply_code(k) <= '1' when bit_k'above(0.5) else '0'       (one A->D assignment per bit)
-- u_supply is the voltage at the ECU's battery terminals, so it includes the drop across the battery's
-- internal resistance under motor current.
--
-- Sign convention (passive, IEEE 1076.1.1): every contact quantity is u = v(common) - v(fixed contact)
-- and i = current from the motor terminal through the contact to bat_p/bat_n. The motor current of the up
-- state flows bat_p -> mot_p (i_up_no < 0) and mot_n -> bat_n (i_down_nc > 0).
--
-- Generics: r_contact (per closed contact; the thesis gives none: 0 = ideal relay, real contacts and
-- their wiring are some 5 .. 20 mOhm).
-- Limits: no relay operate/release time and no bounce (a relay switches at the time its signal changes),
-- no current drawn by the electronics itself, no freewheeling/suppression circuit, ideal open contacts.
entity ecu_hardware is
  generic (
    r_contact : resistance := ecu_hardware_r_contact);  -- resistance of a closed relay contact (0 = ideal)
  port (
    terminal bat_p, bat_n       : electrical;          -- battery plus, minus
    terminal mot_p, mot_n       : electrical;          -- motor plus, minus
    signal relay_up, relay_down : in std_logic;        -- relay coils ('1' = energised)
    signal supply_code          : out std_logic_vector(7 downto 0));  -- supply voltage [0.1 V]
end entity ecu_hardware;

architecture behavioral of ecu_hardware is
  constant lsb : real := 0.1;  -- [V] voltage step of supply_code

  -- contacts of relay_up (common mot_p) and relay_down (common mot_n): voltage [V], current [A]
  quantity u_up_no across i_up_no through mot_p to bat_p;      -- relay_up, normally-open contact
  quantity u_up_nc across i_up_nc through mot_p to bat_n;      -- relay_up, normally-closed contact
  quantity u_down_no across i_down_no through mot_n to bat_p;  -- relay_down, normally-open contact
  quantity u_down_nc across i_down_nc through mot_n to bat_n;  -- relay_down, normally-closed contact
  quantity u_supply across bat_p to bat_n;                     -- supply voltage [V] at the ECU

  quantity code : real;  -- [1] supply voltage in steps of lsb, 0 .. 255
  quantity bit0 : real;  -- [1] bit 0 (LSB) of code, 0/1
  quantity bit1 : real;  -- [1] bit 1 of code, 0/1
  quantity bit2 : real;  -- [1] bit 2 of code, 0/1
  quantity bit3 : real;  -- [1] bit 3 of code, 0/1
  quantity bit4 : real;  -- [1] bit 4 of code, 0/1
  quantity bit5 : real;  -- [1] bit 5 of code, 0/1
  quantity bit6 : real;  -- [1] bit 6 of code, 0/1
  quantity bit7 : real;  -- [1] bit 7 (MSB) of code, 0/1
begin
  assert r_contact >= 0.0 report "ecu_hardware: r_contact must be >= 0" severity failure;

  -- The contact equations switch when a relay signal changes: the analog solution restarts there (1076.1).
  break on relay_up, relay_down;

  if relay_up = '1' use
    u_up_no == r_contact * i_up_no;  -- closed
    i_up_nc == 0.0;                  -- open
  else
    i_up_no == 0.0;                  -- open
    u_up_nc == r_contact * i_up_nc;  -- closed
  end use;

  if relay_down = '1' use
    u_down_no == r_contact * i_down_no;  -- closed
    i_down_nc == 0.0;                    -- open
  else
    i_down_no == 0.0;                    -- open
    u_down_nc == r_contact * i_down_nc;  -- closed
  end use;

  code == realmin(255.0, realmax(0.0, floor(u_supply / lsb + 0.5)));
  bit0 == bit_of(code, 0);
  bit1 == bit_of(code, 1);
  bit2 == bit_of(code, 2);
  bit3 == bit_of(code, 3);
  bit4 == bit_of(code, 4);
  bit5 == bit_of(code, 5);
  bit6 == bit_of(code, 6);
  bit7 == bit_of(code, 7);

  supply_code(0) <= '1' when bit0'above(0.5) else '0';
  supply_code(1) <= '1' when bit1'above(0.5) else '0';
  supply_code(2) <= '1' when bit2'above(0.5) else '0';
  supply_code(3) <= '1' when bit3'above(0.5) else '0';
  supply_code(4) <= '1' when bit4'above(0.5) else '0';
  supply_code(5) <= '1' when bit5'above(0.5) else '0';
  supply_code(6) <= '1' when bit6'above(0.5) else '0';
  supply_code(7) <= '1' when bit7'above(0.5) else '0';
end architecture behavioral;
