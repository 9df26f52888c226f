-- Family 10: type time, time literals and a time generic converted to real seconds.
-- period = 1 ms (generic of type time); tp = real(period / 1 ns)*1.0e-9 = 1.0e-3 s.
--   v(t) = sin(2*pi*t/tp)
-- A process toggles the boolean phase every period/4 = 250 us (first at 250 us); q = 1 when phase else 0:
--   q(t) = floor(t/250 us) mod 2
library ieee;
use ieee.math_real.all;

entity time_generic_tb is
  generic (period : time := 1 ms);
end entity time_generic_tb;

architecture behav of time_generic_tb is
  constant tp : real := real(period / 1 ns) * 1.0e-9;
  constant quarter : time := period / 4;
  signal phase : boolean := false;
  quantity v, q : real;
begin
  toggler : process is
  begin
    wait for quarter;
    phase <= not phase;
  end process toggler;

  v == sin(math_2_pi * now / tp);
  if phase use
    q == 1.0;
  else
    q == 0.0;
  end use;
  break on phase;
end architecture behav;
