library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;

-- tb_worm_gear_architectures: the three worm-gear architectures side by side (thesis 4.1.2.6, Fig. 4.30),
-- each parametrized to the same forward efficiency eta_target (46.3 %) and ratio 1:73, each in its own copy
-- of the self-locking test bench of Fig. 4.28 (motor of params/self_locking_bench.txt, rotational spring on
-- the gear wheel, one piecewise-linear supply: +u_supply for t_on, off for t_off, -u_supply for t_on, off).
--
-- Parametrization (4.1.2.6: "Reduction ratio is achieved in 2D and 3D architectures by proper values of lead
-- angle, radius of worm and gear. Adapting friction coefficients of bearing and contacting face can reach
-- the purpose to change power efficiency"):
--   behavioral: ratio = 73, eta = eta_target.
--   two_d, three_d: lead angle 6 deg (the thesis's example), r_gear 29.2 mm (assumed, module 0.8 mm x 73
--   teeth), r_worm = r_gear/(73*tan(lead_angle)) (Eq. 4.14e solved for r_w); bearings lubricated plain
--   bearings, mu_bearing = 0.05 (handbook range 0.05-0.1) with friction radii 2.5 mm (armature/worm shaft,
--   5 mm) and 4 mm (gear axle, 8 mm) -- assumed, the thesis gives no drawing; press angle 11.5 deg
--   (4.1.2.5). The contact friction coefficient is then the one free parameter: the steady driving
--   efficiency of worm_gear(three_d) (its header) solved for mu_contact, separately for two_d (press angle
--   0) and three_d, by contact_friction_for below.
-- Measured by the bench: efficiency = gear output energy / worm input energy over the first powered phase.
-- Circuit per architecture X (beh, 2d, 3d): supply -- motor_X -- gear_X -- load_X (spring to the housing).
-- Generics: eta_target, lead_angle, r_gear, press_angle, mu_bearing, r_bearing_worm, r_bearing_gear,
-- u_supply, stiffness, t_on, t_off, ramp_time.
-- bench: worm-gear-architectures; parameter set: params/self_locking_bench.txt
entity tb_worm_gear_architectures is
  generic (
    eta_target     : real              := 0.463;         -- [1] forward efficiency of every architecture
    lead_angle     : angle              := 0.1047197551;  -- lead angle of two_d/three_d (6 deg)
    r_gear         : displacement              := 29.2e-3;       -- pitch radius of the gear wheel (two_d/three_d)
    press_angle    : angle              := 0.2007128640;  -- press angle of three_d (11.5 deg)
    mu_bearing     : real              := 0.05;          -- [1] bearing friction coefficient (two_d/three_d)
    r_bearing_worm : displacement              := 2.5e-3;        -- friction radius of the worm-shaft bearing
    r_bearing_gear : displacement              := 4.0e-3;        -- friction radius of the gear-axle bearing
    u_supply       : voltage              := 13.0;          -- magnitude of the supply voltage
    stiffness      : angular_stiffness := 0.3;           -- torsional stiffness of each load spring
    t_on           : real              := 4.0;           -- [s] duration of each powered phase
    t_off          : real              := 1.0;           -- [s] pause between the two powered phases
    ramp_time      : real              := 0.01);         -- [s] duration of each voltage ramp of the source
end entity tb_worm_gear_architectures;

architecture structural of tb_worm_gear_architectures is
  constant ratio : real := 73.0;  -- [1] gear ratio of every architecture (thesis 4.1.2.6: 1:73)

  -- Contact friction coefficient mu_c for which worm_gear(three_d) with press angle pa has the steady
  -- driving efficiency eta_t (see the three_d header):
  --   eta*i*(r_w*(cos_p*sin_l + mu_c*cos_l) + mu_b*r_bw*k) = r_g*(cos_p*cos_l - mu_c*sin_l) - mu_b*r_bg*k
  -- is linear in mu_c for a fixed k = sqrt(1 + mu_c**2); iterating on k contracts by about mu_b*mu_c per
  -- step, so eight steps are exact to machine precision.
  function contact_friction_for(eta_t, pa, lead, i, r_w, r_g, mu_b, r_bw, r_bg : real) return real is
    variable k  : real := 1.0;  -- [1] resultant contact force per unit normal force
    variable mu : real := 0.0;  -- [1] contact friction coefficient
  begin
    for n in 1 to 8 loop
      mu := (r_g * cos(pa) * cos(lead) - mu_b * k * (r_bg + eta_t * i * r_bw)
             - eta_t * i * r_w * cos(pa) * sin(lead))
            / (eta_t * i * r_w * cos(lead) + r_g * sin(lead));
      k := sqrt(1.0 + mu * mu);
    end loop;
    return mu;
  end function contact_friction_for;

  constant r_worm : real := r_gear / (ratio * tan(lead_angle));  -- [m] worm pitch radius, Eq. 4.14e
  constant mu_c_2d : real := contact_friction_for(eta_target, 0.0, lead_angle, ratio, r_worm, r_gear,
                                                  mu_bearing, r_bearing_worm, r_bearing_gear);  -- [1] two_d
  constant mu_c_3d : real := contact_friction_for(eta_target, press_angle, lead_angle, ratio, r_worm, r_gear,
                                                  mu_bearing, r_bearing_worm, r_bearing_gear);  -- [1] three_d

  terminal supply_p : electrical;                   -- supply plus = plus of every motor
  terminal armature_beh, armature_2d, armature_3d : rotational_v;  -- motor armatures = worm shafts
  terminal wheel_beh, wheel_2d, wheel_3d : rotational_v;         -- gear wheels = spring ends
begin
  assert eta_target > 0.0 and eta_target < 1.0
    report "tb_worm_gear_architectures: eta_target must be > 0 and < 1" severity failure;
  assert mu_c_2d >= 0.0 and mu_c_3d >= 0.0
    report "tb_worm_gear_architectures: eta_target is unreachable: the bearing friction alone gives less"
    severity failure;
  assert ramp_time > 0.0 and ramp_time < t_off
    report "tb_worm_gear_architectures: ramp_time must be > 0 and < t_off" severity failure;

  supply: entity work.pwl_supply(behavioral)
    generic map (
      times  => (0.0, ramp_time, t_on, t_on + ramp_time, t_on + t_off, t_on + t_off + ramp_time,
                 2.0 * t_on + t_off, 2.0 * t_on + t_off + ramp_time),
      values => (0.0, u_supply, u_supply, 0.0, 0.0, -u_supply, -u_supply, 0.0))
    port map (p => supply_p, n => electrical_ref);

  motor_beh: entity work.dcpm_motor(simple)
    port map (p => supply_p, n => electrical_ref, shaft => armature_beh);
  gear_beh: entity work.worm_gear(behavioral)
    generic map (ratio => ratio, eta => eta_target)
    port map (worm => armature_beh, gear => wheel_beh);
  load_beh: entity work.rotational_spring(linear)
    generic map (stiffness => stiffness)
    port map (shaft_a => wheel_beh, shaft_b => rotational_velocity_ref);

  motor_2d: entity work.dcpm_motor(simple)
    port map (p => supply_p, n => electrical_ref, shaft => armature_2d);
  gear_2d: entity work.worm_gear(two_d)
    generic map (r_worm => r_worm, r_gear => r_gear, lead_angle => lead_angle, mu_contact => mu_c_2d,
                 mu_bearing => mu_bearing, r_bearing_worm => r_bearing_worm, r_bearing_gear => r_bearing_gear)
    port map (worm => armature_2d, gear => wheel_2d);
  load_2d: entity work.rotational_spring(linear)
    generic map (stiffness => stiffness)
    port map (shaft_a => wheel_2d, shaft_b => rotational_velocity_ref);

  motor_3d: entity work.dcpm_motor(simple)
    port map (p => supply_p, n => electrical_ref, shaft => armature_3d);
  gear_3d: entity work.worm_gear(three_d)
    generic map (r_worm => r_worm, r_gear => r_gear, lead_angle => lead_angle, press_angle => press_angle,
                 mu_contact => mu_c_3d, mu_bearing => mu_bearing, r_bearing_worm => r_bearing_worm,
                 r_bearing_gear => r_bearing_gear)
    port map (worm => armature_3d, gear => wheel_3d);
  load_3d: entity work.rotational_spring(linear)
    generic map (stiffness => stiffness)
    port map (shaft_a => wheel_3d, shaft_b => rotational_velocity_ref);
end architecture structural;
