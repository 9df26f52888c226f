-- Family 1: RL step response.
-- A step source u drives r in series with l (tau = l/r = 1 ms):
--   il(t) = (u/r)*(1 - exp(-t*r/l)),  vl(t) = u*exp(-t*r/l).
library ieee;
use ieee.electrical_systems.all;

entity rl_step_tb is
  generic (u : voltage := 1.0; r : resistance := 10.0; l : inductance := 10.0e-3);
end entity rl_step_tb;

architecture behav of rl_step_tb is
  terminal a, b : electrical;
  quantity vs across isrc through a to electrical_ref;
  quantity vr across ir through a to b;
  quantity vl across il through b to electrical_ref;
begin
  if domain = quiescent_domain use
    vs == 0.0;
  else
    vs == u;
  end use;
  vr == r * ir;
  vl == l * il'dot;
end architecture behav;
