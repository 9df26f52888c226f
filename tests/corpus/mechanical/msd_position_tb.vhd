-- Family 6 and 7: translational (displacement) nature, free vibration from a break-list initial value.
-- m = 0.5 kg, k = 200 N/m, d = 2 N*s/m: w0 = 20 rad/s, zeta = 0.1, sigma = 2 1/s, wd = w0*sqrt(1 - zeta**2).
-- Released at x0 = 10 mm with zero speed (break x => 0.01, vel => 0.0):
--   x(t) = x0*exp(-sigma*t)*(cos(wd*t) + sigma/wd*sin(wd*t))
library ieee;
use ieee.mechanical_systems.all;

entity msd_position_tb is
  generic (m : mass := 0.5; k : stiffness := 200.0; d : damping := 2.0; x0 : displacement := 0.01);
end entity msd_position_tb;

architecture behav of msd_position_tb is
  terminal p : translational;
  quantity x across fm through p to translational_ref;
  quantity xk across fk through p to translational_ref;
  quantity xd across fd through p to translational_ref;
  quantity vel : velocity;
begin
  vel == x'dot;
  fm == m * vel'dot;
  fk == k * xk;
  fd == d * vel;
  break x => x0, vel => 0.0;
end architecture behav;
