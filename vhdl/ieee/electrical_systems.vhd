-- IEEE.ELECTRICAL_SYSTEMS, as in IEEE Std 1076.1.1, written for tools that do not ship it.
-- Compile into library IEEE. Only the declarations this project uses are given.
--
-- Sign convention (electrical): across = voltage of the plus terminal against the minus terminal [V];
-- through = current flowing from the plus terminal through the model to the minus terminal [A].
-- across * through is the power the model absorbs [W].
package electrical_systems is
  subtype voltage is real tolerance "default_voltage";          -- [V]
  subtype current is real tolerance "default_current";          -- [A]
  subtype charge is real tolerance "default_charge";            -- [C]
  subtype resistance is real tolerance "default_resistance";    -- [Ohm]
  subtype conductance is real tolerance "default_conductance";  -- [S]
  subtype capacitance is real tolerance "default_capacitance";  -- [F]
  subtype inductance is real tolerance "default_inductance";    -- [H]
  subtype power is real tolerance "default_power";              -- [W]

  nature electrical is voltage across current through electrical_ref reference;
end package electrical_systems;
