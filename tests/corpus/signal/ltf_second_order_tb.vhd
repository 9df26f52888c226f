-- Family 8: 'ltf, second-order low pass H(s) = w**2/(w**2 + 2*zeta*w*s + s**2), w = 1000 rad/s, zeta = 0.5,
-- aggregates given in place; unit step input from t = 0:
--   y(t) = 1 - exp(-zeta*w*t)*(cos(wd*t) + zeta*w/wd*sin(wd*t)),  wd = w*sqrt(1 - zeta**2)
library ieee;
use ieee.electrical_systems.all;

entity ltf_second_order_tb is
end entity ltf_second_order_tb;

architecture behav of ltf_second_order_tb is
  terminal n_in, n_out : electrical;
  quantity vin across iin through n_in to electrical_ref;
  quantity vout across iout through n_out to electrical_ref;
begin
  if domain = quiescent_domain use
    vin == 0.0;
  else
    vin == 1.0;
  end use;
  vout == vin'ltf((0 => 1.0e6), (1.0e6, 1.0e3, 1.0));
end architecture behav;
