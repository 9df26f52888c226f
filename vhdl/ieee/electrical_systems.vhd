-- IEEE.ELECTRICAL_SYSTEMS, as in IEEE Std 1076.1.1, written for tools that do not ship it.
-- Compile into library IEEE. The names are the standard's; the comments are this project's. `power` is not the
-- standard's here (it is in IEEE.ENERGY_SYSTEMS, with the same tolerance and unit): the project's models use it.
--
-- Sign convention (electrical): across = voltage of the plus terminal against the minus terminal [V];
-- through = current flowing from the plus terminal through the model to the minus terminal [A].
-- across * through is the power the model absorbs [W].
-- Sign convention (magnetic, the same): across = magnetomotive force of the plus terminal against the minus
-- terminal [A]; through = magnetic flux from the plus terminal through the model to the minus terminal [Wb].
library ieee;
use ieee.fundamental_constants.all;

package electrical_systems is
  subtype voltage is real tolerance "default_voltage";          -- [V]
  subtype current is real tolerance "default_current";          -- [A]
  subtype charge is real tolerance "default_charge";            -- [C]
  subtype resistance is real tolerance "default_resistance";    -- [Ohm]
  subtype conductance is real tolerance "default_conductance";  -- [S]
  subtype capacitance is real tolerance "default_capacitance";  -- [F]
  subtype inductance is real tolerance "default_inductance";    -- [H]
  subtype power is real tolerance "default_power";              -- [W]
  subtype mmf is real tolerance "default_mmf";                                          -- [A]
  subtype electric_flux is real tolerance "default_flux";                               -- [C]
  subtype electric_flux_density is real tolerance "default_flux_density";               -- [C/m**2]
  subtype electric_field_strength is real tolerance "default_field_strength";           -- [V/m]
  subtype magnetic_flux is real tolerance "default_flux";                               -- [Wb]
  subtype magnetic_flux_density is real tolerance "default_flux_density";               -- [T]
  subtype magnetic_field_strength is real tolerance "default_field_strength";           -- [A/m]
  subtype reluctance is real tolerance "default_reluctance";                            -- [A/Wb]

  attribute unit of voltage : subtype is "volt";
  attribute unit of current : subtype is "ampere";
  attribute unit of charge : subtype is "coulomb";
  attribute unit of resistance : subtype is "ohm";
  attribute unit of conductance : subtype is "siemens";
  attribute unit of capacitance : subtype is "farad";
  attribute unit of mmf : subtype is "ampere";
  attribute unit of electric_flux : subtype is "coulomb";
  attribute unit of electric_flux_density : subtype is "coulomb/meter^2";
  attribute unit of electric_field_strength : subtype is "volt/meter";
  attribute unit of magnetic_flux : subtype is "weber";
  attribute unit of magnetic_flux_density : subtype is "tesla";
  attribute unit of magnetic_field_strength : subtype is "ampere/meter";
  attribute unit of inductance : subtype is "henry";
  attribute unit of reluctance : subtype is "ampere/weber";
  attribute symbol of voltage : subtype is "V";
  attribute symbol of current : subtype is "A";
  attribute symbol of charge : subtype is "C";
  attribute symbol of resistance : subtype is "Ohm";
  attribute symbol of conductance : subtype is "S";
  attribute symbol of capacitance : subtype is "F";
  attribute symbol of mmf : subtype is "A";
  attribute symbol of electric_flux : subtype is "C";
  attribute symbol of electric_flux_density : subtype is "C/m^2";
  attribute symbol of electric_field_strength : subtype is "V/m";
  attribute symbol of magnetic_flux : subtype is "Wb";
  attribute symbol of magnetic_flux_density : subtype is "T";
  attribute symbol of magnetic_field_strength : subtype is "A/m";
  attribute symbol of inductance : subtype is "H";
  attribute symbol of reluctance : subtype is "A/Wb";

  nature electrical is voltage across current through electrical_ref reference;
  nature electrical_vector is array (natural range <>) of electrical;
  nature magnetic is mmf across magnetic_flux through magnetic_ref reference;
  nature magnetic_vector is array (natural range <>) of magnetic;

  -- The standard declares the vector subtypes of the across and through types as n_vector'across and
  -- n_vector'through; GHDL 5 stops on those with an internal error, so they are written as the real_vector
  -- subtypes they denote (same tolerance group).
  subtype voltage_vector is real_vector tolerance "default_voltage";  -- [V]
  subtype current_vector is real_vector tolerance "default_current";  -- [A]
  subtype mmf_vector is real_vector tolerance "default_mmf";  -- [A]
  subtype magnetic_flux_vector is real_vector tolerance "default_flux";  -- [Wb]

  subtype charge_vector is real_vector tolerance "default_charge";  -- [C]
  subtype resistance_vector is real_vector tolerance "default_resistance";  -- [Ohm]
  subtype conductance_vector is real_vector tolerance "default_conductance";  -- [S]
  subtype capacitance_vector is real_vector tolerance "default_capacitance";  -- [F]
  subtype electric_flux_vector is real_vector tolerance "default_flux";  -- [C]
  subtype electric_flux_density_vector is real_vector tolerance "default_flux_density";  -- [C/m**2]
  subtype electric_field_strength_vector is real_vector tolerance "default_field_strength";  -- [V/m]
  subtype magnetic_flux_density_vector is real_vector tolerance "default_flux_density";  -- [T]
  subtype magnetic_field_strength_vector is real_vector tolerance "default_field_strength";  -- [A/m]
  subtype inductance_vector is real_vector tolerance "default_inductance";  -- [H]
  subtype reluctance_vector is real_vector tolerance "default_reluctance";  -- [A/Wb]

  alias ground is electrical_ref;
end package electrical_systems;
