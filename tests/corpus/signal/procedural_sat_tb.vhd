-- Family 11: a procedural with a variable and if/elsif computing a saturation.
-- x = 2*sin(2*pi*50*t);   y = max(-1, min(1, x))
library ieee;
use ieee.math_real.all;

entity procedural_sat_tb is
  generic (limit_value : real := 1.0);
end entity procedural_sat_tb;

architecture behav of procedural_sat_tb is
  quantity x, y : real;
begin
  x == 2.0 * sin(math_2_pi * 50.0 * now);
  procedural is
    variable a : real;
  begin
    a := x;
    if a > limit_value then
      a := limit_value;
    elsif a < -limit_value then
      a := -limit_value;
    end if;
    y := a;
  end procedural;
end architecture behav;
