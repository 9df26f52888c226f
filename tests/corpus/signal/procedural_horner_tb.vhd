-- Family 11: a procedural with a for loop (Horner scheme) assigning two quantities.
-- x = 1000*t (0..2 over 2 ms), coefficients c = (1.0, -2.0, 0.5, 0.25) in ascending powers:
--   p(x)  = 1 - 2*x + 0.5*x**2 + 0.25*x**3,   dp(x) = -2 + x + 0.75*x**2
library ieee;
use ieee.math_real.all;

entity procedural_horner_tb is
end entity procedural_horner_tb;

architecture behav of procedural_horner_tb is
  constant coeffs : real_vector(0 to 3) := (1.0, -2.0, 0.5, 0.25);
  quantity x, p, dp : real;
begin
  x == 1000.0 * now;
  procedural is
    variable acc, dacc : real;
  begin
    acc := coeffs(3);
    dacc := 0.0;
    for k in 2 downto 0 loop
      dacc := dacc * x + acc;
      acc := acc * x + coeffs(k);
    end loop;
    p := acc;
    dp := dacc;
  end procedural;
end architecture behav;
