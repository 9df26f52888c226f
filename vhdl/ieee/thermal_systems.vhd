-- IEEE.THERMAL_SYSTEMS, as in IEEE Std 1076.1.1, written for tools that do not ship it.
-- Compile into library IEEE. The names are the standard's; the comments are this project's.
--
-- Sign convention (thermal, the same as electrical): across = temperature of the plus terminal against the
-- minus terminal [K] (against thermal_ref: a temperature rise over the reference, e.g. ambient);
-- through = heat flow from the plus terminal through the model to the minus terminal [W].
library ieee;
use ieee.fundamental_constants.all;

package thermal_systems is
  subtype temperature is real tolerance "default_temperature";                  -- [K]
  subtype heat_flow is real tolerance "default_heat_flow";                      -- [W]
  subtype thermal_capacitance is real tolerance "default_thermal_capacitance";  -- [J/K]
  subtype thermal_resistance is real tolerance "default_thermal_resistance";    -- [K/W]
  subtype thermal_conductance is real tolerance "default_thermal_conductance";  -- [W/K]

  attribute unit of temperature : subtype is "kelvin";
  attribute unit of heat_flow : subtype is "watt";
  attribute unit of thermal_capacitance : subtype is "joule/kelvin";
  attribute unit of thermal_resistance : subtype is "kelvin/watt";
  attribute unit of thermal_conductance : subtype is "watt/kelvin";
  attribute symbol of temperature : subtype is "K";
  attribute symbol of heat_flow : subtype is "W";
  attribute symbol of thermal_capacitance : subtype is "J/K";
  attribute symbol of thermal_resistance : subtype is "K/W";
  attribute symbol of thermal_conductance : subtype is "W/K";

  nature thermal is temperature across heat_flow through thermal_ref reference;
  nature thermal_vector is array (natural range <>) of thermal;

  -- The standard declares the vector subtypes of the across and through types as n_vector'across and
  -- n_vector'through; GHDL 5 stops on those with an internal error, so they are written as the real_vector
  -- subtypes they denote (same tolerance group).
  subtype temperature_vector is real_vector tolerance "default_temperature";  -- [K]
  subtype heat_flow_vector is real_vector tolerance "default_heat_flow";  -- [W]

  subtype thermal_capacitance_vector is real_vector tolerance "default_thermal_capacitance";  -- [J/K]
  subtype thermal_resistance_vector is real_vector tolerance "default_thermal_resistance";  -- [K/W]
  subtype thermal_conductance_vector is real_vector tolerance "default_thermal_conductance";  -- [W/K]
end package thermal_systems;
