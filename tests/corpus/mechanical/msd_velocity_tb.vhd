-- Family 6: translational_v mass-spring-damper, force step.
-- m = 1 kg, k = 400 N/m (spring force = k*integral of velocity), d = 8 N*s/m, F = 4 N from t = 0:
-- w0 = 20 rad/s, zeta = 0.2, sigma = zeta*w0 = 4 1/s, wd = w0*sqrt(1 - zeta**2):
--   x(t)  = F/k*(1 - exp(-sigma*t)*(cos(wd*t) + sigma/wd*sin(wd*t)))      spring force fk = k*x
--   v(t)  = F/k*(w0**2/wd)*exp(-sigma*t)*sin(wd*t)
library ieee;
use ieee.mechanical_systems.all;

entity msd_velocity_tb is
  generic (m : mass := 1.0; k : stiffness := 400.0; d : damping := 8.0; f0 : force := 4.0);
end entity msd_velocity_tb;

architecture behav of msd_velocity_tb is
  terminal p : translational_v;
  quantity vm across fm through p to translational_velocity_ref;
  quantity vk across fk through p to translational_velocity_ref;
  quantity vd across fd through p to translational_velocity_ref;
  quantity ff through p to translational_velocity_ref;          -- the force source (negative: pushes p)
begin
  fm == m * vm'dot;
  fk == k * vk'integ;
  fd == d * vd;
  if domain = quiescent_domain use
    ff == 0.0;
  else
    ff == -f0;
  end use;
end architecture behav;
