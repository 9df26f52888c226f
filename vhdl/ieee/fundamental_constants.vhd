-- IEEE.FUNDAMENTAL_CONSTANTS, as in IEEE Std 1076.1.1, written for tools that do not ship it.
-- Compile into library IEEE. The names and values are the standard's; the comments are this project's.
--
-- The standard takes its physical constants from the NIST (CODATA 1998) tables and keeps them when later
-- CODATA adjustments change the last digits: phys_q and phys_k are known to about 4e-8 and 2e-6 relative
-- (their stated uncertainties), phys_h to about 8e-8; phys_eps0, phys_mu0, phys_c, phys_gravity and
-- phys_ctok are exact by definition (in the SI of the time). The attributes UNIT and SYMBOL declared here are
-- the ones the other 1076.1.1 packages attach to their subtypes.
library ieee;
use ieee.math_real.all;

package fundamental_constants is
  attribute unit : string;      -- full name of a subtype's unit, e.g. "volt"
  attribute symbol : string;    -- its abbreviation, e.g. "V"

  constant phys_q : real := 1.602_176_462e-19;              -- [C] elementary charge
  constant phys_eps0 : real := 8.854_187_817e-12;           -- [F/m] electric constant (vacuum permittivity)
  constant phys_mu0 : real := 4.0e-7 * math_pi;             -- [H/m] magnetic constant (vacuum permeability)
  constant phys_k : real := 1.380_650_3e-23;                -- [J/K] Boltzmann constant
  constant phys_gravity : real := 9.806_65;                 -- [m/s**2] standard acceleration of gravity
  constant phys_ctok : real := 273.15;                      -- [K] 0 degC in kelvin (add to a Celsius value)
  constant phys_c : real := 299_792_458.0;                  -- [m/s] speed of light in vacuum
  constant phys_h : real := 6.626_068_76e-34;               -- [J*s] Planck constant
  constant phys_h_over_2_pi : real := phys_h / math_2_pi;   -- [J*s] reduced Planck constant

  -- SI prefixes as scale factors
  constant yocto : real := 1.0e-24;
  constant zepto : real := 1.0e-21;
  constant atto : real := 1.0e-18;
  constant femto : real := 1.0e-15;
  constant pico : real := 1.0e-12;
  constant nano : real := 1.0e-9;
  constant micro : real := 1.0e-6;
  constant milli : real := 1.0e-3;
  constant centi : real := 1.0e-2;
  constant deci : real := 1.0e-1;
  constant deka : real := 1.0e+1;
  constant hecto : real := 1.0e+2;
  constant kilo : real := 1.0e+3;
  constant mega : real := 1.0e+6;
  constant giga : real := 1.0e+9;
  constant tera : real := 1.0e+12;
  constant peta : real := 1.0e+15;
  constant exa : real := 1.0e+18;
  constant zetta : real := 1.0e+21;
  constant yotta : real := 1.0e+24;
  alias deca is deka;                                       -- the other spelling of the prefix 10**1
end package fundamental_constants;
