-- IEEE.MATERIAL_CONSTANTS, as in IEEE Std 1076.1.1, written for tools that do not ship it.
-- Compile into library IEEE. The names and typical values are the standard's; the comments are this project's.
--
-- Material properties and the environment are measured, not fundamental: the standard fixes the names as
-- deferred constants and gives typical values in the package body (NIST tables and J. Lau, "Thermal Stress and
-- Strain in Microelectronics Packaging"), so that a user may compile a body of their own with other values.
-- To use other values, compile a body of your own in place of the one below.
package material_constants is
  constant phys_eps_si : real;                -- [1] relative permittivity of silicon
  constant phys_eps_sio2 : real;              -- [1] relative permittivity of silicon dioxide
  constant phys_e_si : real;                  -- [Pa] Young's modulus of silicon
  constant phys_e_sio2 : real;                -- [Pa] Young's modulus of silicon dioxide
  constant phys_e_poly : real;                -- [Pa] Young's modulus of polysilicon (the standard's value)
  constant phys_nu_si : real;                 -- [1] Poisson's ratio of silicon (100 orientation)
  constant phys_nu_poly : real;               -- [1] Poisson's ratio of polysilicon
  constant phys_rho_poly : real;              -- [kg/m**3] density of polysilicon
  constant phys_rho_sio2 : real;              -- [kg/m**3] density of silicon dioxide
  constant ambient_temperature : real;        -- [K]
  constant ambient_pressure : real;           -- [Pa]
  constant ambient_illuminance : real;        -- [lx] daylight
end package material_constants;

package body material_constants is
  constant phys_eps_si : real := 11.7;
  constant phys_eps_sio2 : real := 3.9;
  constant phys_e_si : real := 190.0e+9;
  constant phys_e_sio2 : real := 73.0e+9;
  constant phys_e_poly : real := 1.62e+9;
  constant phys_nu_si : real := 0.28;
  constant phys_nu_poly : real := 0.22;
  constant phys_rho_poly : real := 2330.0;
  constant phys_rho_sio2 : real := 2220.0;
  constant ambient_temperature : real := 298.15;
  constant ambient_pressure : real := 100_000.0;
  constant ambient_illuminance : real := 30_000.0;
end package body material_constants;
