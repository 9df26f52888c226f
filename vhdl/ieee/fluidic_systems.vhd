-- IEEE.FLUIDIC_SYSTEMS, as in IEEE Std 1076.1.1, written for tools that do not ship it.
-- Compile into library IEEE. The names are the standard's; the comments are this project's.
--
-- Two natures, both with pressure across (plus terminal against minus terminal [Pa]):
--   fluidic: an incompressible medium, through = volume flow from the plus terminal through the model to the
--   minus terminal [m**3/s]; compressible_fluidic: a compressible medium, through = mass flow [kg/s].
-- The cf* subtypes are the compressible counterparts of fresistance, fcapacitance, inertance, fconductance.
library ieee;
use ieee.fundamental_constants.all;

package fluidic_systems is
  subtype pressure is real tolerance "default_pressure";              -- [Pa]
  subtype vflow_rate is real tolerance "default_vflow_rate";          -- [m**3/s]
  subtype mass_flow_rate is real tolerance "default_mass_flow_rate";  -- [kg/s]
  subtype volume is real tolerance "default_volume";                  -- [m**3]
  subtype density is real tolerance "default_density";                -- [kg/m**3]
  subtype viscosity is real tolerance "default_viscosity";            -- [Pa*s]
  subtype fresistance is real tolerance "default_fresistance";        -- [Pa*s/m**3]
  subtype fconductance is real tolerance "default_fconductance";      -- [m**3/(Pa*s)]
  subtype fcapacitance is real tolerance "default_fcapacitance";      -- [m**3/Pa]
  subtype inertance is real tolerance "default_inertance";            -- [Pa*s**2/m**3]
  subtype cfresistance is real tolerance "default_cfresistance";      -- [Pa*s/kg]
  subtype cfcapacitance is real tolerance "default_cfcapacitance";    -- [kg/Pa]
  subtype cfinertance is real tolerance "default_cfinertance";        -- [Pa*s**2/kg]
  subtype cfconductance is real tolerance "default_cfconductance";    -- [kg/(Pa*s)]

  attribute unit of pressure : subtype is "pascal";
  attribute unit of vflow_rate : subtype is "meter^3/second";
  attribute unit of mass_flow_rate : subtype is "kilogram/second";
  attribute unit of volume : subtype is "meter^3";
  attribute unit of density : subtype is "kilogram/meter^3";
  attribute unit of viscosity : subtype is "pascal*second";
  attribute unit of fresistance : subtype is "pascal*second/meter^3";
  attribute unit of fconductance : subtype is "meter^3/(pascal*second)";
  attribute unit of fcapacitance : subtype is "meter^3/pascal";
  attribute unit of inertance : subtype is "pascal*second^2/meter^3";
  attribute unit of cfresistance : subtype is "pascal*second/kilogram";
  attribute unit of cfcapacitance : subtype is "kilogram/pascal";
  attribute unit of cfinertance : subtype is "pascal*second^2/kilogram";
  attribute unit of cfconductance : subtype is "kilogram/(pascal*second)";
  attribute symbol of pressure : subtype is "Pa";
  attribute symbol of vflow_rate : subtype is "m^3/s";
  attribute symbol of mass_flow_rate : subtype is "kg/s";
  attribute symbol of volume : subtype is "m^3";
  attribute symbol of density : subtype is "kg/m^3";
  attribute symbol of viscosity : subtype is "Pa*s";
  attribute symbol of fresistance : subtype is "Pa*s/m^3";
  attribute symbol of fconductance : subtype is "m^3/(Pa*s)";
  attribute symbol of fcapacitance : subtype is "m^3/Pa";
  attribute symbol of inertance : subtype is "Pa*s^2/m^3";
  attribute symbol of cfresistance : subtype is "Pa*s/kg";
  attribute symbol of cfcapacitance : subtype is "kg/Pa";
  attribute symbol of cfinertance : subtype is "Pa*s^2/kg";
  attribute symbol of cfconductance : subtype is "kg/(Pa*s)";

  nature fluidic is pressure across vflow_rate through fluidic_ref reference;
  nature fluidic_vector is array (natural range <>) of fluidic;
  nature compressible_fluidic is pressure across mass_flow_rate through compressible_fluidic_ref reference;
  nature compressible_fluidic_vector is array (natural range <>) of compressible_fluidic;

  -- The standard declares the vector subtypes of the across and through types as n_vector'across and
  -- n_vector'through; GHDL 5 stops on those with an internal error, so they are written as the real_vector
  -- subtypes they denote (same tolerance group).
  subtype pressure_vector is real_vector tolerance "default_pressure";  -- [Pa]
  subtype vflow_rate_vector is real_vector tolerance "default_vflow_rate";  -- [m**3/s]
  subtype mass_flow_rate_vector is real_vector tolerance "default_mass_flow_rate";  -- [kg/s]

  subtype volume_vector is real_vector tolerance "default_volume";  -- [m**3]
  subtype density_vector is real_vector tolerance "default_density";  -- [kg/m**3]
  subtype viscosity_vector is real_vector tolerance "default_viscosity";  -- [Pa*s]
  subtype fresistance_vector is real_vector tolerance "default_fresistance";  -- [Pa*s/m**3]
  subtype fconductance_vector is real_vector tolerance "default_fconductance";  -- [m**3/(Pa*s)]
  subtype fcapacitance_vector is real_vector tolerance "default_fcapacitance";  -- [m**3/Pa]
  subtype inertance_vector is real_vector tolerance "default_inertance";  -- [Pa*s**2/m**3]
  subtype cfresistance_vector is real_vector tolerance "default_cfresistance";  -- [Pa*s/kg]
  subtype cfconductance_vector is real_vector tolerance "default_cfconductance";  -- [kg/(Pa*s)]
  subtype cfcapacitance_vector is real_vector tolerance "default_cfcapacitance";  -- [kg/Pa]
  subtype cfinertance_vector is real_vector tolerance "default_cfinertance";  -- [Pa*s**2/kg]
end package fluidic_systems;
