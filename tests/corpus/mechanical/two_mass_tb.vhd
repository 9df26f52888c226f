-- Families 5 and 6: structural mechanical chain of mass, spring and damper entities (translational_v).
-- Force F = 2 N on m1 = 1 kg; spring k1 = 100 N/m between m1 and m2 = 0.5 kg; m2 tied to the frame by
-- k2 = 50 N/m and damper d2 = 3 N*s/m; damper d1 = 1 N*s/m from m1 to the frame.
--   m1*v1' = F - d1*v1 - k1*(x1 - x2),  m2*v2' = k1*(x1 - x2) - k2*x2 - d2*v2,  x' = v
-- Reference: SciPy solve_ivp.
library ieee;
use ieee.mechanical_systems.all;

entity tm_mass is
  generic (m : mass := 1.0);
  port (terminal p : translational_v);
end entity tm_mass;

architecture newton of tm_mass is
  quantity v across f through p to translational_velocity_ref;
begin
  f == m * v'dot;
end architecture newton;

library ieee;
use ieee.mechanical_systems.all;

entity tm_spring is
  generic (k : stiffness := 1.0);
  port (terminal p, q : translational_v);
end entity tm_spring;

architecture hooke of tm_spring is
  quantity dv across f through p to q;
begin
  f == k * dv'integ;
end architecture hooke;

library ieee;
use ieee.mechanical_systems.all;

entity tm_damper is
  generic (d : damping := 1.0);
  port (terminal p, q : translational_v);
end entity tm_damper;

architecture viscous of tm_damper is
  quantity dv across f through p to q;
begin
  f == d * dv;
end architecture viscous;

library ieee;
use ieee.mechanical_systems.all;

entity tm_force is
  generic (f0 : force := 1.0);
  port (terminal p : translational_v);
end entity tm_force;

architecture step of tm_force is
  quantity f through p to translational_velocity_ref;
begin
  if domain = quiescent_domain use
    f == 0.0;
  else
    f == -f0;
  end use;
end architecture step;

library ieee;
use ieee.mechanical_systems.all;

entity two_mass_tb is
end entity two_mass_tb;

architecture structural of two_mass_tb is
  terminal p1, p2 : translational_v;
  quantity v1 across p1 to translational_velocity_ref;
  quantity v2 across p2 to translational_velocity_ref;
begin
  drive : entity work.tm_force(step) generic map (f0 => 2.0) port map (p => p1);
  mass1 : entity work.tm_mass(newton) generic map (m => 1.0) port map (p => p1);
  damp1 : entity work.tm_damper(viscous) generic map (d => 1.0) port map (p => p1, q => translational_velocity_ref);
  link : entity work.tm_spring(hooke) generic map (k => 100.0) port map (p => p1, q => p2);
  mass2 : entity work.tm_mass(newton) generic map (m => 0.5) port map (p => p2);
  tie : entity work.tm_spring(hooke) generic map (k => 50.0) port map (p => p2, q => translational_velocity_ref);
  damp2 : entity work.tm_damper(viscous) generic map (d => 3.0) port map (p => p2, q => translational_velocity_ref);
end architecture structural;
