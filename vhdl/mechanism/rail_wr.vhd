library IEEE;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_params.all;

-- rail_wr: macro model of the rail-guided cable window-regulator mechanism (thesis 4.2.2.3, Fig. 4.65;
-- 5.1 b). One entity, two realisations with the same two pins, "shaft" (to the drive) and "glass" (to the
-- door), so a bench swaps the variant by naming the other architecture and nothing else:
--   double_rail  two rails, three bowdens, four rotatable pulleys, two sliders behind a lever (Fig. 4.62,
--                4.65; the common variant);
--   single_rail  one rail, two bowdens, two rotatable pulleys, one slider.
-- The components are connected in the order of the real system (4.2.2.3). Parameters common to all
-- instances of a component (friction coefficients, spring data, slider coefficients, lever ratio, rail stop)
-- come from the parameter set's component sections ([cable_drum], [bowden], [pulley], [compressing_spring],
-- [slider], [lever], [rail_stop]); what differs from instance to instance (wrap angles) and what a bench
-- varies (drum diameter, start position) are generics of this entity.
--
-- Cable loop (double_rail), in the direction of the cable tension falling while the glass is lifted; every
-- element's cable_a faces the drum's upper port (see cable_drum):
--   drum.cable_a - spring_up - bowden_1 - pulley_1 (top of rail A) - slider_a - pulley_2 (bottom of rail A)
--   - bowden_2 (crossing) - pulley_3 (top of rail B) - slider_b - pulley_4 (bottom of rail B) - bowden_3
--   - spring_down - drum.cable_b;  lever: glass <- slider_a (ratio_a), slider_b (1 - ratio_a);
--   rail_stop on the glass pin.
-- single_rail: drum.cable_a - spring_up - bowden_1 - pulley_1 (top) - slider - pulley_2 (bottom) - bowden_2
--   - spring_down - drum.cable_b; the slider carries the glass directly; rail_stop on the glass pin.
-- The compressing springs sit at the drum housing (bowden ends), as in Fig. 4.62; their compressions
-- spring_up.compression and spring_down.compression show the tension distribution (4.2.2.2 a).
--
-- Velocity form: the cable and glass terminals are of nature translational_v (across = velocity); the
-- elements that need a position (springs, rail stop) integrate their velocities from their state at t = 0:
-- the springs start at their spacer compression, the glass at glass_position0.
-- Sign convention: shaft speed positive = lifting (wr_common); glass velocity/position positive upwards,
-- position 0 = the glass on the bottom rail stop (window fully open).
-- The mechanism takes the drive torque at shaft (through > 0 while lifting) and delivers the lifting force
-- to the glass pin (through < 0 while lifting).
--
-- Generics: drum_diameter (2*r_cd; 5.3.3 studies 40 .. 48 mm), glass_position0 (glass position at t = 0,
-- e.g. a bench starting half way up; the door model needs the same value), tension_state (-1 .. 1: the
-- tension distribution the loop starts with, 4.2.2.2 c: 0 = as assembled, +1 = as left by a lifting stroke
-- (upper spring pressed to block), -1 = as left by a lowering stroke (lower spring pressed to block)), bowden_alpha (wrap angles of the bowdens in loop order:
-- 3 for double_rail, 2 for single_rail), pulley_alpha (wrap angles of the pulleys in loop order: 4 for
-- double_rail, 2 for single_rail).
-- Limits: those of the components; no cable elasticity besides the springs (4.2.1), no slack.
entity rail_wr is
  generic (
    drum_diameter   : displacement := rail_wr_drum_diameter;    -- cable drum (wrapping) diameter
    glass_position0 : displacement := rail_wr_glass_position0;  -- glass position at t = 0
    tension_state   : real         := rail_wr_tension_state;    -- [1] tension distribution at t = 0
    bowden_alpha    : real_vector  := rail_wr_bowden_alpha;     -- [rad] bowden wrap angles, loop order
    pulley_alpha    : real_vector  := rail_wr_pulley_alpha);    -- [rad] pulley wrap angles, loop order
  port (
    terminal shaft : rotational_v;    -- drive output shaft (cable drum)
    terminal glass : translational_v);  -- glass pin (lower edge of the glass)
end entity rail_wr;

architecture single_rail of rail_wr is
  terminal up_0, up_1, up_2, top, bottom, down_2, down_1, down_0 : translational_v;  -- cable nodes, loop order
begin
  assert drum_diameter > 0.0 report "rail_wr: drum_diameter must be > 0" severity failure;
  assert abs(tension_state) <= 1.0 report "rail_wr: tension_state must be in [-1, 1]" severity failure;
  assert bowden_alpha'length = 2 report "rail_wr: single_rail needs 2 bowden_alpha values" severity failure;
  assert pulley_alpha'length = 2 report "rail_wr: single_rail needs 2 pulley_alpha values" severity failure;

  drum: entity work.cable_drum(behavioral)
    generic map (r_cd => 0.5 * drum_diameter)
    port map (shaft => shaft, cable_a => up_0, cable_b => down_0);
  spring_up: entity work.compressing_spring(extended)
    generic map (state => tension_state)
    port map (cable_a => up_0, cable_b => up_1);
  bowden_1: entity work.bowden(capstan)
    generic map (alpha => bowden_alpha(bowden_alpha'low))
    port map (cable_a => up_1, cable_b => up_2);
  pulley_1: entity work.pulley(behavioral)
    generic map (alpha => pulley_alpha(pulley_alpha'low))
    port map (cable_a => up_2, cable_b => top);
  slider: entity work.slider(behavioral)
    port map (cable_a => top, cable_b => bottom, glass => glass);
  pulley_2: entity work.pulley(behavioral)
    generic map (alpha => pulley_alpha(pulley_alpha'low + 1))
    port map (cable_a => bottom, cable_b => down_2);
  bowden_2: entity work.bowden(capstan)
    generic map (alpha => bowden_alpha(bowden_alpha'low + 1))
    port map (cable_a => down_2, cable_b => down_1);
  spring_down: entity work.compressing_spring(extended)
    generic map (state => -tension_state)
    port map (cable_a => down_1, cable_b => down_0);
  stop: entity work.rail_stop(behavioral)
    generic map (position0 => glass_position0)
    port map (glass => glass);
end architecture single_rail;

architecture double_rail of rail_wr is
  terminal up_0, up_1, up_2, a_top, a_bottom, cross_1, cross_2, b_top, b_bottom, down_2, down_1, down_0
    : translational_v;                        -- cable nodes, loop order
  terminal pin_a, pin_b : translational_v;    -- glass pins of the two sliders (lever arms)
begin
  assert drum_diameter > 0.0 report "rail_wr: drum_diameter must be > 0" severity failure;
  assert abs(tension_state) <= 1.0 report "rail_wr: tension_state must be in [-1, 1]" severity failure;
  assert bowden_alpha'length = 3 report "rail_wr: double_rail needs 3 bowden_alpha values" severity failure;
  assert pulley_alpha'length = 4 report "rail_wr: double_rail needs 4 pulley_alpha values" severity failure;

  drum: entity work.cable_drum(behavioral)
    generic map (r_cd => 0.5 * drum_diameter)
    port map (shaft => shaft, cable_a => up_0, cable_b => down_0);
  spring_up: entity work.compressing_spring(extended)
    generic map (state => tension_state)
    port map (cable_a => up_0, cable_b => up_1);
  bowden_1: entity work.bowden(capstan)
    generic map (alpha => bowden_alpha(bowden_alpha'low))
    port map (cable_a => up_1, cable_b => up_2);
  pulley_1: entity work.pulley(behavioral)
    generic map (alpha => pulley_alpha(pulley_alpha'low))
    port map (cable_a => up_2, cable_b => a_top);
  slider_a: entity work.slider(behavioral)
    port map (cable_a => a_top, cable_b => a_bottom, glass => pin_a);
  pulley_2: entity work.pulley(behavioral)
    generic map (alpha => pulley_alpha(pulley_alpha'low + 1))
    port map (cable_a => a_bottom, cable_b => cross_1);
  bowden_2: entity work.bowden(capstan)
    generic map (alpha => bowden_alpha(bowden_alpha'low + 1))
    port map (cable_a => cross_1, cable_b => cross_2);
  pulley_3: entity work.pulley(behavioral)
    generic map (alpha => pulley_alpha(pulley_alpha'low + 2))
    port map (cable_a => cross_2, cable_b => b_top);
  slider_b: entity work.slider(behavioral)
    port map (cable_a => b_top, cable_b => b_bottom, glass => pin_b);
  pulley_4: entity work.pulley(behavioral)
    generic map (alpha => pulley_alpha(pulley_alpha'low + 3))
    port map (cable_a => b_bottom, cable_b => down_2);
  bowden_3: entity work.bowden(capstan)
    generic map (alpha => bowden_alpha(bowden_alpha'low + 2))
    port map (cable_a => down_2, cable_b => down_1);
  spring_down: entity work.compressing_spring(extended)
    generic map (state => -tension_state)
    port map (cable_a => down_1, cable_b => down_0);
  lever: entity work.lever(behavioral)
    port map (glass => glass, pin_a => pin_a, pin_b => pin_b);
  stop: entity work.rail_stop(behavioral)
    generic map (position0 => glass_position0)
    port map (glass => glass);
end architecture double_rail;
