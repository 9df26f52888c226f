-- Family 17: index constraints are honoured by indexing, 'left/'right/'low/'high and 'range loops: a constant
-- real_vector(1 to 3), a constant of a subtype real_vector(2 downto 0), the generic real_vector(1 to 2) of an
-- instance; and a std_ulogic port of an analog entity. All values are static:
--   a = c(1) + 10*d(0) = 1 + 10*6 = 61;  b = c'left + c'high + d'left + d'low = 1 + 3 + 2 + 0 = 6;
--   s = sum over k in c'range of k*c(k) = 1 + 4 + 9 = 14;  y = gains(2)*u = 20*0.5 = 10.
library ieee;
use ieee.std_logic_1164.all;
use ieee.math_real.all;

entity scale is
  generic (gains : real_vector(1 to 2) := (10.0, 20.0));
  port (signal en : in std_ulogic; quantity u : in real; quantity y : out real);
end entity scale;

architecture a of scale is
begin
  y == gains(2) * u;
end architecture a;

library ieee;
use ieee.std_logic_1164.all;
use ieee.math_real.all;

entity constrained_vector_tb is
end entity constrained_vector_tb;

architecture behav of constrained_vector_tb is
  subtype triple is real_vector(2 downto 0);
  constant c : real_vector(1 to 3) := (1.0, 2.0, 3.0);
  constant d : triple := (4.0, 5.0, 6.0);
  signal en : std_ulogic := '1';
  quantity a, b, s, u, y : real;
begin
  a == c(1) + 10.0 * d(0);
  b == real(c'left + c'high + d'left + d'low);
  procedural is
    variable acc : real;
  begin
    acc := 0.0;
    for k in c'range loop
      acc := acc + real(k) * c(k);
    end loop;
    s := acc;
  end procedural;
  u == 0.5;
  dut : entity work.scale port map (en => en, u => u, y => y);
end architecture behav;
