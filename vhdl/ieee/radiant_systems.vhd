-- IEEE.RADIANT_SYSTEMS, as in IEEE Std 1076.1.1, written for tools that do not ship it.
-- Compile into library IEEE. The names are the standard's; the comments are this project's.
--
-- Nature radiant: across = luminous intensity of the plus terminal against the minus terminal [cd];
-- through = luminous flux from the plus terminal through the model to the minus terminal [lm].
library ieee;
use ieee.fundamental_constants.all;

package radiant_systems is
  subtype illuminance is real tolerance "default_illuminance";                -- [lx]
  subtype luminous_flux is real tolerance "default_luminous_flux";            -- [lm]
  subtype luminous_intensity is real tolerance "default_luminous_intensity";  -- [cd]
  subtype irradiance is real tolerance "default_irradiance";                  -- [W/m**2]

  attribute unit of illuminance : subtype is "lux";
  attribute unit of luminous_flux : subtype is "lumen";
  attribute unit of luminous_intensity : subtype is "candela";
  attribute unit of irradiance : subtype is "watt/meter^2";
  attribute symbol of illuminance : subtype is "lx";
  attribute symbol of luminous_flux : subtype is "lm";
  attribute symbol of luminous_intensity : subtype is "cd";
  attribute symbol of irradiance : subtype is "W/m^2";

  nature radiant is luminous_intensity across luminous_flux through radiant_ref reference;
  nature radiant_vector is array (natural range <>) of radiant;

  -- The standard declares the vector subtypes of the across and through types as n_vector'across and
  -- n_vector'through; GHDL 5 stops on those with an internal error, so they are written as the real_vector
  -- subtypes they denote (same tolerance group).
  subtype luminous_intensity_vector is real_vector tolerance "default_luminous_intensity";  -- [cd]
  subtype luminous_flux_vector is real_vector tolerance "default_luminous_flux";  -- [lm]

  subtype illuminance_vector is real_vector tolerance "default_illuminance";  -- [lx]
  subtype irradiance_vector is real_vector tolerance "default_irradiance";  -- [W/m**2]
end package radiant_systems;
