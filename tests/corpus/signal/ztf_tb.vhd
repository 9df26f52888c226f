-- Family 8: 'ztf, H(z) = 0.5/(1 - 0.5*z**-1) (ascending powers of z**-1), sample period 1 ms,
-- first sample at 0.5 ms (initial delay). Unit step input from t = 0; before the first sample y holds its
-- quiescent value 0. y[n] = 0.5*u + 0.5*y[n-1]:
--   y(t) = 1 - 0.5**(n+1) for 0.5 ms + n*1 ms <= t < 0.5 ms + (n+1)*1 ms,  y(t) = 0 for t < 0.5 ms
library ieee;
use ieee.math_real.all;

entity ztf_tb is
  generic (period : real := 1.0e-3);   -- [s]
end entity ztf_tb;

architecture behav of ztf_tb is
  constant num : real_vector := (0 => 0.5);
  constant den : real_vector := (1.0, -0.5);
  quantity u, y : real;
begin
  if domain = quiescent_domain use
    u == 0.0;
  else
    u == 1.0;
  end use;
  y == u'ztf(num, den, period, 0.5 * period);
end architecture behav;
