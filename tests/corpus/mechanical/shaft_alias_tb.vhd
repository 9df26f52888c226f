-- Family 15: nature'reference and aliases (alias shaft_ref is rotational_v'reference; a subtype alias).
-- Flywheel j = 0.02 kg*m**2 spinning at 50 rad/s (break list) braked by a damper b = 0.1 N*m*s/rad
-- (tau = j/b = 0.2 s):   w(t) = 50*exp(-5*t),  damper torque = b*w
library ieee;
use ieee.mechanical_systems.all;

entity shaft_alias_tb is
  generic (j : moment_inertia := 0.02; b : angular_damping := 0.1; w0 : angular_velocity := 50.0);
end entity shaft_alias_tb;

architecture behav of shaft_alias_tb is
  alias shaft_ref is rotational_v'reference;
  alias speed is angular_velocity;
  terminal shaft : rotational_v;
  constant w_start : speed := w0;
  quantity w across tj through shaft to shaft_ref;
  quantity wb across tb through shaft to shaft_ref;
begin
  tj == j * w'dot;
  tb == b * wb;
  break w => w_start;
end architecture behav;
