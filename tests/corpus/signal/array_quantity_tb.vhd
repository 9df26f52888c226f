-- Family 13: a constrained array subtype and an array quantity (real_vector(1 to 3)).
-- A cascade of three first-order lags (tau = 1 ms each) after a unit step:
--   q1' = (u - q1)/tau, q2' = (q1 - q2)/tau, q3' = (q2 - q3)/tau;  with s = t/tau:
--   q1 = 1 - exp(-s),  q2 = 1 - exp(-s)*(1 + s),  q3 = 1 - exp(-s)*(1 + s + s**2/2)
library ieee;
use ieee.math_real.all;

entity array_quantity_tb is
  generic (tau : real := 1.0e-3);   -- [s]
end entity array_quantity_tb;

architecture behav of array_quantity_tb is
  subtype triple is real_vector(1 to 3);
  quantity u : real;
  quantity q : triple;
begin
  if domain = quiescent_domain use
    u == 0.0;
  else
    u == 1.0;
  end use;
  q(1)'dot == (u - q(1)) / tau;
  q(2)'dot == (q(1) - q(2)) / tau;
  q(3)'dot == (q(2) - q(3)) / tau;
end architecture behav;
