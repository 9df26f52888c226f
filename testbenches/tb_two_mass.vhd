library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;

-- tb_two_mass: numerical simulation of the analytical two-mass model (thesis 3.1.2.3, Fig. 3.2/3.3) for both
-- friction cases side by side, with the thesis's "typical values" M_1 = 45 kg, M_2 = 5 kg, c = 2e4 N/m,
-- mu = 80 N*s/m, omega = 75.8 1/s:
--   case1: friction on the relative velocity (3.1.2.1, Eq. 3.2), F_a = 200 N, F_r = 10 N ("internal");
--   case2: friction on the velocity of M_2 (3.1.2.2, Eq. 3.13), F_a = 1800 N, F_r = 90 N ("external").
-- Both start from the thesis's initial condition a(0) = 0.01, xi(0) = 0, V(0) = 0, i.e. a relative
-- displacement z0 = a0*L with the length scale L = F_a/(M_1*omega_0**2*|2 - nu**2|) (3.1.2.3, after [76]),
-- omega_0**2 = c*(M_1 + M_2)/(2*M_1*M_2), nu = omega/omega_0, both masses at rest, centre of mass at 0.
-- The bench compares the settled amplitude of case1.z / case2.z with the stationary amplitude of the
-- averaged system (Eq. 3.12 = 3.19) and integrates the averaged system next to it (wrsim.analytic).
-- The masses' terminals are connected to nothing else (no external force): exactly Eq. 3.2 / 3.13.
-- Generics: m1, m2, c, mu, omega, f_a1, f_r1 (case 1), f_a2, f_r2 (case 2), a0.
-- bench: two-mass; parameter set: params/fpg2_12nm.txt
entity tb_two_mass is
  generic (
    m1    : mass      := 45.0;    -- equivalent armature mass M_1
    m2    : mass      := 5.0;     -- glass mass M_2
    c     : stiffness := 2.0e4;   -- system stiffness
    mu    : damping   := 80.0;    -- damping factor
    omega : real      := 75.8;    -- [1/s] angular frequency of the driving force
    f_a1  : force     := 200.0;   -- driving force amplitude, case 1
    f_r1  : force     := 10.0;    -- friction force amplitude, case 1
    f_a2  : force     := 1800.0;  -- driving force amplitude, case 2
    f_r2  : force     := 90.0;    -- friction force amplitude, case 2
    a0    : real      := 0.01);   -- [1] initial dimensionless amplitude a(0)
end entity tb_two_mass;

architecture structural of tb_two_mass is
  constant omega0 : real := sqrt(c * (m1 + m2) / (2.0 * m1 * m2));  -- [1/s] time scale omega_0
  constant detune : real := abs(2.0 - (omega / omega0)**2);          -- [1] |2 - nu**2|
  terminal armature_1, glass_1, armature_2, glass_2 : translational;  -- M_1 and M_2 of each case
begin
  assert detune > 0.0
    report "tb_two_mass: omega must differ from the main resonance sqrt(2)*omega_0 (the length scale L is undefined there)"
    severity failure;

  case1: entity work.two_mass(exact)
    generic map (m1 => m1, m2 => m2, c => c, mu => mu, f_a => f_a1, omega => omega, f_r => f_r1,
                 relative_friction => true, z0 => a0 * f_a1 / (m1 * omega0**2 * detune))
    port map (mass_1 => armature_1, mass_2 => glass_1);

  case2: entity work.two_mass(exact)
    generic map (m1 => m1, m2 => m2, c => c, mu => mu, f_a => f_a2, omega => omega, f_r => f_r2,
                 relative_friction => false, z0 => a0 * f_a2 / (m1 * omega0**2 * detune))
    port map (mass_1 => armature_2, mass_2 => glass_2);
end architecture structural;
