library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_params.all;

-- compressing_spring: compressing ("compensation") spring of the rail window-regulator mechanism, extended
-- model (thesis 4.2.1.4, Fig. 4.53; 4.2.2.2, Fig. 4.62/4.63): a linear spring in parallel with a stop
-- (two stops: the spring's free length and its block), plus a spacer that pre-compresses the spring so the
-- closed cable loop is under tension at drum angle 0. The spring sits in series in the cable (between the
-- drum housing and a bowden sheath); its compression is the "eye" on the tension distribution (Fig. 4.62):
-- while lifting, the upper spring is pressed (into block), the lower one relaxes, and vice versa.
--
-- Equations:
--   compression  c = c_0 + integral of (v_a - v_b) dt         (c_0 = spacer at t = 0, Fig. 4.63: the pins are
--                                                              at the same position, the spring has the
--                                                              spacer's deformation: the loop's tension)
--                c_0 = spacer + state*(travel_block - spacer)  (state: the tension distribution the loop
--                                                              starts with, see below)
--   tension      T = k*c                                      normal working range 0 <= c <= travel_block
--                  + k_block*(c - travel_block) for c > travel_block   (block; 4.2.2.2: the block stiffness is
--                                                              the system stiffness of the mechanism)
--                  0                            if this sum is negative: the cable cannot push, it slackens
--                                                 (only at stall or in a pinch; in normal operation both
--                                                 springs stay compressed, 4.2.2.2 a)
--   tension == realmax(0.0, k*compression + k_block*realmax(0.0, compression - travel_block))
--
-- Sign convention (passive, IEEE 1076.1.1; cable loop of vhdl/mechanism, velocity form): dv = v_a - v_b
-- [m/s], positive when the a-side cable runs ahead of the b-side (which presses the spring); tension = force
-- [N] taken from cable_a and passed on to cable_b = cable tension.
--
-- Generics: k (normal working stiffness, thesis 1000 .. 6000 N/m), travel_block (compression at which the
-- coils touch; the force at block k*travel_block lies in the thesis's working range 25 .. 140 N), k_block
-- (block stiffness = system stiffness C_wr, 20 .. 40 N/mm, 27.6 N/mm measured, Eq. 4.42), spacer (spacer
-- length = pre-compression at drum angle 0; the two springs' spacers set the loop tension), state (-1 .. 1:
-- the tension distribution at t = 0 as a state, not a parameter: 0 = as assembled, +1 = pressed to block by
-- the cable its partner (with state -1) gave up, as after a stroke that pulled on this side, 4.2.2.2 c).
-- Limits: no damping, no coil-to-coil progression below block; the spring's free-length stop of Fig. 4.53 is
-- replaced by slack (a cable cannot carry compression).
entity compressing_spring is
  generic (
    k            : stiffness    := compressing_spring_k;             -- spring stiffness in the normal working range
    travel_block : displacement := compressing_spring_travel_block;  -- compression at which the spring goes into block
    k_block      : stiffness    := compressing_spring_k_block;       -- block stiffness = system stiffness of the mechanism
    spacer       : displacement := compressing_spring_spacer;        -- spacer length: compression at zero cable elongation
    state        : real         := compressing_spring_state);        -- [1] tension distribution at t = 0 (-1 .. 1, see header)
  port (
    terminal cable_a, cable_b : translational_v);  -- cable side towards the drum's upper port, other side
end entity compressing_spring;

architecture extended of compressing_spring is
  -- relative cable velocity across the spring [m/s] and the cable tension [N] through it
  quantity dv across tension through cable_a to cable_b;
  quantity compression : displacement;  -- spring compression c (spacer + elongation)
begin
  assert k > 0.0 report "compressing_spring: k must be > 0" severity failure;
  assert travel_block > 0.0 report "compressing_spring: travel_block must be > 0" severity failure;
  assert k_block > 0.0 report "compressing_spring: k_block must be > 0" severity failure;
  assert spacer >= 0.0 report "compressing_spring: spacer must be >= 0" severity failure;
  assert spacer < travel_block report "compressing_spring: spacer must be < travel_block" severity failure;
  assert abs(state) <= 1.0 report "compressing_spring: state must be in [-1, 1]" severity failure;

  compression == spacer + state * (travel_block - spacer) + dv'integ;
  tension == realmax(0.0, k * compression + k_block * realmax(0.0, compression - travel_block));
end architecture extended;
