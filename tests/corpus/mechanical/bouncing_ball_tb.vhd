-- Family 7: bouncing ball, break with 'when' re-initialising the velocity at each impact.
-- Dropped from h = 1 m at rest, g = 9.81 m/s**2, restitution e = 0.8:
--   first impact t1 = sqrt(2*h/g) = 0.451524 s with speed v1 = sqrt(2*g*h);
--   after impact n the ball leaves at e**n*v1, flies 2*e**n*v1/g and peaks at e**(2n)*h (0.64 m, 0.4096 m, ...);
--   impacts at 0.451524, 1.173953, 1.751896, 2.214250 s.
library ieee;
use ieee.mechanical_systems.all;

entity bouncing_ball_tb is
  generic (h : displacement := 1.0; g : acceleration := 9.81; e : real := 0.8);
end entity bouncing_ball_tb;

architecture behav of bouncing_ball_tb is
  quantity x : displacement;
  quantity v : velocity;
begin
  x'dot == v;
  v'dot == -g;
  break x => h, v => 0.0;
  break v => -e * v when not x'above(0.0);
end architecture behav;
