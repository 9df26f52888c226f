-- IEEE_PROPOSED natures, family 6/7: translational_v mass coasting against a damper from an initial speed.
-- m = 2 kg, d = 4 N*s/m, v0 = 3 m/s (break list):   v(t) = 3*exp(-2*t),  damper force fd = d*v
library ieee_proposed;
use ieee_proposed.mechanical_systems.all;

entity msd_proposed_tb is
  generic (m : mass := 2.0; d : damping := 4.0; v0 : velocity := 3.0);
end entity msd_proposed_tb;

architecture behav of msd_proposed_tb is
  terminal p : translational_v;
  quantity v across fm through p;
  quantity vd across fd through p;
begin
  fm == m * v'dot;
  fd == d * vd;
  break v => v0;
end architecture behav;
