library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use work.wr_common.all;
use work.wr_params.all;

-- pwl_supply: piecewise-linear voltage source, e.g. the switched supply of the worm-gear test bench
-- (thesis 4.1.2.6, Fig. 4.28: +U for 4 s, 1 s off, -U for 4 s, off).
--
-- Equation: the terminal voltage interpolates the table (times, values) linearly in the simulation time and
-- holds the first/last value before/after the table (wr_common.table_lookup):
--   ua == table_lookup(now, times, values)
-- An ideal source: "off" (value 0) short-circuits the load, as a relay or H-bridge that connects both motor
-- leads to ground does (the motor is then braked by its own back-EMF).
--
-- Sign convention (passive, IEEE 1076.1.1): ua = v(p) - v(n) [V]; ia = current into p through the source
-- out of n [A] (< 0 while the source supplies a load).
--
-- Generics: times (strictly increasing, at least two points), values (same length).
-- Limits: no internal resistance, no current limit; corners of the table are not announced to the solver
-- (give the ramps a duration of several max steps).
entity pwl_supply is
  generic (
    times  : real_vector := pwl_supply_times;    -- [s] breakpoints of the voltage table, strictly increasing
    values : real_vector := pwl_supply_values);  -- [V] source voltage v(p) - v(n) at each breakpoint
  port (
    terminal p, n : electrical);  -- plus, minus
end entity pwl_supply;

architecture behavioral of pwl_supply is
  -- terminal voltage [V] across p-n and current [A] from p through the source to n
  quantity ua across ia through p to n;

begin
  assert times'length = values'length
    report "pwl_supply: times and values must have the same length" severity failure;
  assert times'length >= 2 report "pwl_supply: times needs at least two breakpoints" severity failure;
  assert strictly_increasing(times)
    report "pwl_supply: times must be strictly increasing" severity failure;

  ua == table_lookup(now, times, values);
end architecture behavioral;
