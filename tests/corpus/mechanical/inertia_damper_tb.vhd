-- Family 6: rotational_v inertia + viscous damper + torque step.
-- j = 0.01 kg*m**2, b = 0.1 N*m*s/rad, torque 1 N*m from t = 0 (tau = j/b = 0.1 s):
--   w(t) = (1/b)*(1 - exp(-t*b/j)) = 10*(1 - exp(-10*t)),  damper torque tb = b*w
library ieee;
use ieee.mechanical_systems.all;

entity inertia_damper_tb is
  generic (j : moment_inertia := 0.01; b : angular_damping := 0.1; t0 : torque := 1.0);
end entity inertia_damper_tb;

architecture behav of inertia_damper_tb is
  terminal shaft : rotational_v;
  quantity w across tj through shaft to rotational_velocity_ref;
  quantity wb across tb through shaft to rotational_velocity_ref;
  quantity tsrc through rotational_velocity_ref to shaft;       -- the torque source drives the shaft
begin
  tj == j * w'dot;
  tb == b * wb;
  if domain = quiescent_domain use
    tsrc == 0.0;
  else
    tsrc == t0;
  end use;
end architecture behav;
