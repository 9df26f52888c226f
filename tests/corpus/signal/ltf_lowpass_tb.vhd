-- Family 8: 'ltf, first-order low pass H(s) = 1/(1 + tau*s) (coefficients in ascending powers of s),
-- unit step input from t = 0, tau = 1 ms:   y(t) = 1 - exp(-t/tau)
library ieee;
use ieee.math_real.all;

entity ltf_lowpass_tb is
  generic (tau : real := 1.0e-3);   -- [s]
end entity ltf_lowpass_tb;

architecture behav of ltf_lowpass_tb is
  constant num : real_vector := (0 => 1.0);
  constant den : real_vector := (1.0, tau);
  quantity u, y : real;
begin
  if domain = quiescent_domain use
    u == 0.0;
  else
    u == 1.0;
  end use;
  y == u'ltf(num, den);
end architecture behav;
