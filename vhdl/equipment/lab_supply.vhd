library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;
use IEEE.NUMERIC_STD.all;
use work.wr_params.all;

-- lab_supply: programmable laboratory supply of the closed-loop system benches (thesis 5.1 a: the battery,
-- "an ideal voltage source and a resistance"; 5.3.2: the anti-pinch tests at 9, 13 and 16 V, whose voltage
-- the switch sequence sets with its voltage offset, 4.3.3.2). The battery of the open-loop benches
-- (battery.vhd) has no signal port; this source is the same ideal source with internal resistance whose
-- open-circuit voltage the switch offsets in steps of 0.1 V:
--   u_source = u_nominal + 0.1*to_integer(signed(voltage_offset))            [V]
--   ua == u_source + r_internal*ia        (as dc_supply: ia < 0 while the source delivers current)
-- The offset is a digital input: the source voltage jumps when the switch changes it (the switch changes
-- it only between its P units, with the motor off).
--
-- Sign convention (passive, IEEE 1076.1.1): ua = v(p) - v(n) [V]; ia = current into p through the source
-- out of n [A] (< 0 while supplying a load).
--
-- Generics: u_nominal (open-circuit voltage at offset 0), r_internal (>= 0).
-- Limits: offset range -12.8 .. +12.7 V (8-bit two's complement); no current limit, no dynamics.
entity lab_supply is
  generic (
    u_nominal  : voltage    := lab_supply_u_nominal;    -- open-circuit voltage at offset 0 (thesis: nominal 13 V)
    r_internal : resistance := lab_supply_r_internal);  -- internal resistance of source and wiring
  port (
    terminal p, n         : electrical;                      -- plus, minus
    signal voltage_offset : in std_logic_vector(7 downto 0)); -- [0.1 V] signed offset (switch)
end entity lab_supply;

architecture behavioral of lab_supply is
  -- terminal voltage [V] across p-n and current [A] from p through the source to n (< 0 when supplying)
  quantity ua across ia through p to n;
begin
  assert r_internal >= 0.0 report "lab_supply: r_internal must be >= 0" severity failure;

  break on voltage_offset;   -- the source voltage steps when the switch sets a new offset

  ua == u_nominal + 0.1 * real(to_integer(signed(voltage_offset))) + r_internal * ia;
end architecture behavioral;
