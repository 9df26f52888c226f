-- Family 6: electromechanical DC motor (electrical + rotational_v) on an inertia with viscous friction.
-- u = 12 V step, ra = 1 Ohm, la = 1 mH, ke = kt = 0.05, j = 1e-4 kg*m**2, b = 1e-5 N*m*s/rad:
--   la*ia' = u - ra*ia - ke*w,   j*w' = kt*ia - b*w.   Reference: SciPy solve_ivp.
library ieee;
use ieee.electrical_systems.all;
use ieee.mechanical_systems.all;

entity dc_motor_tb is
  generic (u : voltage := 12.0; ra : resistance := 1.0; la : inductance := 1.0e-3;
           km : real := 0.05;   -- [V*s/rad]
           j : moment_inertia := 1.0e-4; b : angular_damping := 1.0e-5);
end entity dc_motor_tb;

architecture behav of dc_motor_tb is
  terminal p : electrical;
  terminal shaft : rotational_v;
  quantity vs across isrc through p to electrical_ref;
  quantity va across ia through p to electrical_ref;
  quantity w across tm through shaft to rotational_velocity_ref;
  quantity wj across tj through shaft to rotational_velocity_ref;
  quantity wb across tb through shaft to rotational_velocity_ref;
begin
  if domain = quiescent_domain use
    vs == 0.0;
  else
    vs == u;
  end use;
  va == ra * ia + la * ia'dot + km * w;
  tm == -km * ia;
  tj == j * wj'dot;
  tb == b * wb;
end architecture behav;
