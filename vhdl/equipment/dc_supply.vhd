library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use work.wr_params.all;

-- dc_supply: DC voltage source with internal (series) resistance, e.g. the 13 V supply of the motor and
-- drive test stands (thesis 4.1.1.4, 4.1.4.2).
--
-- Equation: terminal voltage = source voltage - internal drop of the DELIVERED current.
--   The through current ia flows from p through the source to n (passive convention), so a source that
--   delivers current into an external load has ia < 0 and the delivered current is -ia:
--     ua = u - r_internal*(-ia)        ua == u + r_internal * ia
--   Written without dividing by r_internal, so r_internal = 0 (ideal source) is allowed.
--
-- Sign convention (passive, IEEE 1076.1.1): ua = v(p) - v(n) [V]; ia = current into p through the source
-- out of n [A]; ua*ia = power the source absorbs (negative while it supplies a load).
--
-- Generics: u (open-circuit voltage, any sign: a negative u reverses the polarity), r_internal (>= 0).
-- Limits: no current limit, no dynamics.
entity dc_supply is
  generic (
    u          : voltage    := dc_supply_u;            -- open-circuit source voltage v(p) - v(n)
    r_internal : resistance := dc_supply_r_internal);  -- internal series resistance (0 = ideal voltage source)
  port (
    terminal p, n : electrical);  -- plus, minus
end entity dc_supply;

architecture behavioral of dc_supply is
  -- terminal voltage [V] across p-n and current [A] from p through the source to n (< 0 when supplying)
  quantity ua across ia through p to n;
begin
  assert r_internal >= 0.0 report "dc_supply: r_internal must be >= 0" severity failure;

  ua == u + r_internal * ia;
end architecture behavioral;
