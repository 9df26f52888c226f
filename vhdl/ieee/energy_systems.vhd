-- IEEE.ENERGY_SYSTEMS, as in IEEE Std 1076.1.1, written for tools that do not ship it.
-- Compile into library IEEE. The names are the standard's; the comments are this project's.
--
-- Energy and power, and the nature unspecified (real_across across, real_through through) for a conservative
-- system of no particular physical domain; its quantities carry no unit, their product is a power when the
-- model says so. The standard gives periodicity, real_across and real_through no unit: they are written
-- dimensionless here.
library ieee;
use ieee.fundamental_constants.all;

package energy_systems is
  subtype energy is real tolerance "default_energy";              -- [J]
  subtype power is real tolerance "default_power";                -- [W]
  subtype periodicity is real tolerance "default_periodicity";    -- [1]
  subtype real_across is real tolerance "default_real_across";    -- [1]
  subtype real_through is real tolerance "default_real_through";  -- [1]

  attribute unit of energy : subtype is "joule";
  attribute unit of power : subtype is "watt";
  attribute symbol of energy : subtype is "J";
  attribute symbol of power : subtype is "W";

  nature unspecified is real_across across real_through through unspecified_ref reference;
  nature unspecified_vector is array (natural range <>) of unspecified;

  -- The standard declares the vector subtypes of the across and through types as n_vector'across and
  -- n_vector'through; GHDL 5 stops on those with an internal error, so they are written as the real_vector
  -- subtypes they denote (same tolerance group).
  subtype energy_vector is real_vector tolerance "default_energy";  -- [J]
  subtype power_vector is real_vector tolerance "default_power";  -- [W]
  subtype periodicity_vector is real_vector tolerance "default_periodicity";  -- [1]
  subtype real_across_vector is real_vector tolerance "default_real_across";  -- [1]
  subtype real_through_vector is real_vector tolerance "default_real_through";  -- [1]
end package energy_systems;
