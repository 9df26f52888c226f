library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;
use work.wr_params.all;

-- slider: glass slider (carrier) on a guide rail of the rail window-regulator mechanism (thesis 4.2.1.5,
-- Fig. 4.54-4.56, Eq. 4.40; rail effects of 4.2.1.6 a): force distributor between the upper cable, the
-- lower cable and the glass, with all frictional losses between slider, cable and rail summed in one force
-- that depends linearly on the slider's load (two characteristic coefficients per slider type).
--
-- Equations:
--   4.40   F_c_up = F_c_dw + F_g,long + F_r      (lifting; F_r changes sign with the velocity)
--          force_a + force_b + cos(reduction_angle)*force_g == f_r
--   friction (Fig. 4.56: F_r linear in the load on the slider, fitted slope and offset):
--          F_r = (f_0 + mu_load*|F_g|)*sgn(v)   f_r == (f_0 + mu_load*abs(force_g))*smooth_sign(v_a, v_threshold)
--   rail reduction angle beta (4.2.1.6 a): the rail deviates by beta from the glass's direction of motion;
--   the glass force is projected onto the rail, F_g,long = F_g*cos(beta), and a slider travel s along the
--   rail moves the glass by s*cos(beta) (same power on both sides):
--          v_g == cos(reduction_angle)*v_a
--   rigid cable through the slider:  v_a == v_b
-- The load distribution ratio of a double-rail mechanism is applied by the `lever` in front of the sliders.
--
-- Sign convention (passive, IEEE 1076.1.1; cable loop of vhdl/mechanism, velocity form): v_a = v_b = slider
-- velocity along the rail [m/s] (positive upwards); force_a = F_c_up taken from the upper cable
-- (cable_a), force_b = -F_c_dw (passed on to the lower cable); force_g = force the slider takes from the
-- glass terminal = -F_g (the slider delivers the lifting force F_g to the glass, F_g > 0 while it carries
-- the glass against gravity and sealing friction).
--
-- Generics: f_0 [N] and mu_load [1] (characteristic coefficients; Fig. 4.56: pads 0.05 .. 0.15 against the
-- rail), reduction_angle [rad], v_threshold [m/s].
-- Limits: no mass; the friction acts on the total load |F_g|, not on the cable forces' bending moments.
entity slider is
  generic (
    f_0             : force    := slider_f_0;              -- friction offset f_0 of the slider type (Fig. 4.56 fit)
    mu_load         : real     := slider_mu_load;          -- [1] friction slope over the slider's load (Fig. 4.56 fit)
    reduction_angle : angle    := slider_reduction_angle;  -- rail reduction angle beta against the glass's direction of motion
    v_threshold     : velocity := slider_v_threshold);     -- slider speed below which sgn(v) is linear in v
  port (
    terminal cable_a, cable_b : translational_v;  -- upper cable (pulls while lifting), lower cable
    terminal glass            : translational_v); -- glass (or lever) pin
end entity slider;

architecture behavioral of slider is
  -- slider velocity [m/s] along the rail and the forces [N] taken from the upper and lower cable
  quantity v_a across force_a through cable_a;
  quantity v_b across force_b through cable_b;
  -- glass pin velocity [m/s] and the force [N] taken from the glass pin (= -F_g)
  quantity v_g across force_g through glass;
  quantity f_r : force;  -- friction force F_r with its sign (Eq. 4.40)
begin
  assert f_0 >= 0.0 report "slider: f_0 must be >= 0" severity failure;
  assert mu_load >= 0.0 and mu_load < 1.0 report "slider: mu_load must be in [0, 1)" severity failure;
  assert abs(reduction_angle) < 0.5 * math_pi
    report "slider: reduction_angle must be in (-pi/2, pi/2) rad" severity failure;
  assert v_threshold > 0.0 report "slider: v_threshold must be > 0" severity failure;

  v_a == v_b;
  v_g == cos(reduction_angle) * v_a;
  f_r == (f_0 + mu_load * abs(force_g)) * smooth_sign(v_a, v_threshold);
  force_a + force_b + cos(reduction_angle) * force_g == f_r;   -- Eq. 4.40
end architecture behavioral;
