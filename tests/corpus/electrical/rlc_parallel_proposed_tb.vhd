-- IEEE_PROPOSED natures, family 1: parallel RLC driven by a current step i0 = 10 mA.
-- r = 100 Ohm, l = 10 mH, c = 1 uF: w0 = 1e4 rad/s, alpha = 1/(2*r*c) = 5000 1/s, wd = sqrt(w0**2 - alpha**2):
--   il(t) = i0*(1 - exp(-alpha*t)*(cos(wd*t) + alpha/wd*sin(wd*t)))
--   v(t)  = l*il'(t) = i0*l*(w0**2/wd)*exp(-alpha*t)*sin(wd*t)
library ieee_proposed;
use ieee_proposed.electrical_systems.all;

entity rlc_parallel_proposed_tb is
  generic (i0 : current := 10.0e-3; r : resistance := 100.0; l : inductance := 10.0e-3;
           c : capacitance := 1.0e-6);
end entity rlc_parallel_proposed_tb;

architecture behav of rlc_parallel_proposed_tb is
  terminal n : electrical;
  quantity isrc through electrical_ref to n;        -- current source driving n
  quantity v across ir through n to electrical_ref;
  quantity vl across il through n to electrical_ref;
  quantity vc across ic through n to electrical_ref;
begin
  if domain = quiescent_domain use
    isrc == 0.0;
  else
    isrc == i0;
  end use;
  v == r * ir;
  vl == l * il'dot;
  ic == c * vc'dot;
end architecture behav;
