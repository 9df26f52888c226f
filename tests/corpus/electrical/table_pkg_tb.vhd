-- Family 4: a package function with a loop over constant real_vector tables (piecewise-linear look-up).
-- A ramp source vs = 1000*t (0..2 V over 2 ms) across a nonlinear conductor whose current is the table
--   v: 0.0  0.5     1.0     2.0
--   i: 0.0  1.0e-3  1.5e-3  4.0e-3        i(t) = interp(1000*t, v, i)
library ieee;
use ieee.electrical_systems.all;

package iv_table is
  constant v_points : real_vector := (0.0, 0.5, 1.0, 2.0);
  constant i_points : real_vector := (0.0, 1.0e-3, 1.5e-3, 4.0e-3);
  function lookup (x : real) return real;
end package iv_table;

package body iv_table is
  function lookup (x : real) return real is
    variable y : real := i_points(i_points'length - 1);
  begin
    if x <= v_points(0) then
      y := i_points(0);
    else
      for k in 1 to v_points'length - 1 loop
        if x > v_points(k - 1) and x <= v_points(k) then
          y := i_points(k - 1) + (i_points(k) - i_points(k - 1)) * (x - v_points(k - 1))
               / (v_points(k) - v_points(k - 1));
        end if;
      end loop;
    end if;
    return y;
  end function lookup;
end package body iv_table;

library ieee;
use ieee.electrical_systems.all;
use work.iv_table.all;

entity table_pkg_tb is
  generic (slope : real := 1.0e3);   -- [V/s]
end entity table_pkg_tb;

architecture behav of table_pkg_tb is
  terminal a : electrical;
  quantity vs across isrc through a to electrical_ref;
  quantity vn across inl through a to electrical_ref;
begin
  vs == slope * now;
  inl == lookup(vn);
end architecture behav;
