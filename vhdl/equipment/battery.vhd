library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use work.wr_params.all;

-- battery: vehicle battery of the window-regulator system bench (thesis 5.1 a: "relatively a simple model,
-- consisting of only an ideal voltage source and a resistance"; nominal voltage 13 V, 4.3.3.1).
-- Structural: the equation is that of dc_supply (ideal source in series with its internal resistance),
-- which this entity instantiates, so the battery and the test-stand supply cannot drift apart:
--   ua = u - r_internal*(delivered current)       (see dc_supply)
--
-- Sign convention (passive, IEEE 1076.1.1): as dc_supply; the battery delivers current out of p, so the
-- through current supply.ia < 0 while it supplies the drive.
--
-- Generics: u (open-circuit voltage), r_internal (internal resistance of battery and wiring, >= 0).
-- Limits: no state of charge, no temperature, no current limit.
entity battery is
  generic (
    u          : voltage    := battery_u;            -- open-circuit voltage (thesis: nominal 13 V)
    r_internal : resistance := battery_r_internal);  -- internal resistance of battery and wiring
  port (
    terminal p, n : electrical);  -- plus, minus
end entity battery;

architecture structural of battery is
begin
  assert r_internal >= 0.0 report "battery: r_internal must be >= 0" severity failure;

  supply: entity work.dc_supply(behavioral)
    generic map (u => u, r_internal => r_internal)
    port map (p => p, n => n);
end architecture structural;
