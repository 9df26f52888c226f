library IEEE;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_params.all;

-- lever: load distributor between the glass and the two sliders of a double-rail window regulator (thesis
-- 5.1 b: "a model of lever is placed between the two sliders in double rail WR", so a single glass pin
-- serves single- and double-rail mechanisms; 4.2.1.5: the distribution ratio, e.g. 60 % on slider B and
-- 40 % on slider A, Fig. 4.55).
--
-- Equations (massless, lossless lever):
--   F_a = ratio_a*F_g, F_b = (1 - ratio_a)*F_g        force_a == -ratio_a*force_g; force_b == -(1 - ratio_a)*force_g
--   v_g = ratio_a*v_a + (1 - ratio_a)*v_b            v_g == ratio_a*v_a + (1.0 - ratio_a)*v_b
--   (virtual work: the lever neither stores nor dissipates power)
--
-- Sign convention (passive, IEEE 1076.1.1; translational_v, velocities positive = glass upwards): force_g = force taken
-- from the glass terminal (= -F_g while the lever lifts the glass); force_a, force_b = forces taken from the
-- slider pins (= F_a, F_b > 0: the sliders push the lever up).
--
-- Generics: ratio_a (share of the glass load carried by pin a, 0 .. 1).
entity lever is
  generic (
    ratio_a : real := lever_ratio_a);  -- [1] share of the glass load on pin a (slider A); pin b carries 1 - ratio_a
  port (
    terminal glass        : translational_v;  -- glass pin
    terminal pin_a, pin_b : translational_v); -- slider pins
end entity lever;

architecture behavioral of lever is
  quantity v_g across force_g through glass;  -- glass velocity [m/s], force [N] taken from the glass pin
  quantity v_a across force_a through pin_a;  -- slider A pin velocity [m/s], force [N] taken from it
  quantity v_b across force_b through pin_b;  -- slider B pin velocity [m/s], force [N] taken from it
begin
  assert ratio_a >= 0.0 and ratio_a <= 1.0 report "lever: ratio_a must be in [0, 1]" severity failure;

  v_g == ratio_a * v_a + (1.0 - ratio_a) * v_b;
  force_a == -ratio_a * force_g;
  force_b == -(1.0 - ratio_a) * force_g;
end architecture behavioral;
