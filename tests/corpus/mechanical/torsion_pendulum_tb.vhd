-- Family 6 and 7: rotational (angle) nature, undamped torsion pendulum from a break-list initial angle.
-- j = 0.01 kg*m**2, k = 1 N*m/rad: w0 = sqrt(k/j) = 10 rad/s; released at 0.1 rad at rest:
--   theta(t) = 0.1*cos(10*t),  spring torque tk = k*theta
library ieee;
use ieee.mechanical_systems.all;

entity torsion_pendulum_tb is
  generic (j : moment_inertia := 0.01; k : angular_stiffness := 1.0; theta0 : angle := 0.1);
end entity torsion_pendulum_tb;

architecture behav of torsion_pendulum_tb is
  terminal disk : rotational;
  quantity theta across tj through disk to rotational_ref;
  quantity th_k across tk through disk to rotational_ref;
  quantity w : angular_velocity;
begin
  w == theta'dot;
  tj == j * w'dot;
  tk == k * th_k;
  break theta => theta0, w => 0.0;
end architecture behav;
