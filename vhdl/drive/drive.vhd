library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;
use work.wr_common.all;
use work.wr_params.all;

-- drive: window-regulator drive = DCPM motor + worm gear + rubber damper + housing friction
-- (thesis 4.1.4, Fig. 4.34, Eq. 4.29-4.31). Structural: the component models are instantiated with
-- their own defaults; parameter sets replace those defaults per entity ([dcpm_motor], [worm_gear],
-- [rubber_damper]), so no motor, gear or damper parameter is passed through this entity.
--
-- Topology (all rotational_v nodes = shaft speeds against the housing, the rotational_v reference):
--   p, n --- motor (dcpm_motor) --- armature --- gear (worm_gear: worm .. gear) --- gear_wheel
--   gear_wheel --- damper (rubber_damper: shaft_a .. shaft_b) --- shaft (drive output)
--   gear_wheel --- housing (rotational_friction, m_c = m_gc)
--
-- Resulting equations in driving mode, steady state, with the damper neglected (thesis 4.1.4.1):
--   4.29a  omega_w = i*omega_g
--   4.29b  M_w*i*eta = M_g (+ M_gc, the housing friction is a load on the gear wheel)
--   4.30a  U_a = R_a*i_a + L_a*di_a/dt + k_e*i*omega_g
--   4.31a  k_t*i_a = M_c + Visc*i*omega_g + J*i*domega_g/dt + (M_g + M_gc)/(i*eta)
-- The housing Coulomb friction M_gc sits at the GEAR WHEEL (housing instance). Its armature-side
-- equivalent in driving mode is M_gc/(i*eta), which is the term Eq. 4.31a adds as "M_gc": the thesis
-- identifies M_gc = 0.4097 N*m as a torque offset of the output characteristic (Fig. 4.42/4.43), i.e. a
-- gear-side value, so it is applied here on the gear side.
-- Eq. 4.30/4.31 neglect the damper; in the model it adds the compliance of Eq. 4.28 between gear wheel
-- and output, so during a torque ramp the output speed is lower than the gear-wheel speed by the
-- deformation rate (dM/dt)/(dM_rd/ddphi).
--
-- Sign convention (passive, IEEE 1076.1.1, rotational_v): p, n as dcpm_motor; at shaft the drive takes torque from the
-- output shaft, i.e. a drive lifting the window (positive rotation) against a load has a negative through
-- torque at shaft. Positive rotation of the output = window closing (wr_common).
--
-- Generics: m_gc (housing Coulomb friction at the gear wheel). Observables: speed_rpm (output shaft),
-- motor.ia, motor.speed_rpm, gear.omega_g (gear wheel), gear.p_gear, damper.deformation.
entity drive is
  generic (
    m_gc : torque := drive_m_gc);  -- Coulomb friction M_gc of gear and housing (Eq. 4.31), acting at the gear wheel
  port (
    terminal p, n  : electrical;       -- motor electrodes (plus, minus)
    terminal shaft : rotational_v;     -- drive output shaft (behind the rubber damper)
    signal hall_a, hall_b : out std_logic;   -- Hall signals of the armature (thesis 5.1: packed in the drive)
    signal direction      : out std_logic);  -- '1' while the armature turns positive (lifting)
end entity drive;

architecture structural of drive is
  terminal armature   : rotational_v;  -- motor armature = worm shaft
  terminal gear_wheel : rotational_v;  -- gear wheel, in front of the rubber damper
  -- output shaft speed [rad/s] against the housing (across only, no element)
  quantity output_speed across shaft;
  quantity speed_rpm : real;  -- [rpm] output shaft speed
begin
  assert m_gc >= 0.0 report "drive: m_gc must be >= 0" severity failure;

  motor: entity work.dcpm_motor(simple)
    port map (p => p, n => n, shaft => armature);

  gear: entity work.worm_gear(behavioral)
    port map (worm => armature, gear => gear_wheel);

  damper: entity work.rubber_damper(behavioral)
    port map (shaft_a => gear_wheel, shaft_b => shaft);

  hall: entity work.hall_sensor(behavioral)
    port map (shaft => armature, hall_a => hall_a, hall_b => hall_b, direction => direction);

  housing: entity work.rotational_friction(behavioral)
    generic map (m_c => m_gc)
    port map (shaft => gear_wheel);

  speed_rpm == output_speed * rpm_per_radps;
end architecture structural;
