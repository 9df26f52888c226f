-- Family 1: RC charge with branch quantities and 'dot.
-- A step source u (0 V in the quiescent domain, u from t = 0) charges c through r:
--   vc(t) = u*(1 - exp(-t/(r*c))),  ic(t) = (u/r)*exp(-t/(r*c)).
library ieee;
use ieee.electrical_systems.all;

entity rc_charge_tb is
  generic (u : voltage := 1.0; r : resistance := 1.0e3; c : capacitance := 1.0e-6);
end entity rc_charge_tb;

architecture behav of rc_charge_tb is
  terminal n_in, n_out : electrical;
  quantity vs across isrc through n_in to electrical_ref;
  quantity vr across ir through n_in to n_out;
  quantity vc across ic through n_out to electrical_ref;
begin
  if domain = quiescent_domain use
    vs == 0.0;
  else
    vs == u;
  end use;
  vr == r * ir;
  ic == c * vc'dot;
end architecture behav;
