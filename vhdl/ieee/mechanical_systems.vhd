-- IEEE.MECHANICAL_SYSTEMS, as in IEEE Std 1076.1.1, written for tools that do not ship it.
-- Compile into library IEEE. Only the declarations this project uses are given.
--
-- Sign convention (all mechanical natures, the same as electrical): across = position/velocity of the
-- plus terminal relative to the minus terminal; through = force/torque flowing from the plus terminal
-- through the model to the minus terminal, i.e. the force/torque the model takes from the plus terminal.
-- across'dot * through is the power the model absorbs [W]. A source that pushes a terminal forward has a
-- negative through quantity there.
package mechanical_systems is
  subtype displacement is real tolerance "default_displacement";                -- [m]
  subtype force is real tolerance "default_force";                              -- [N]
  subtype velocity is real tolerance "default_velocity";                        -- [m/s]
  subtype acceleration is real tolerance "default_acceleration";                -- [m/s**2]
  subtype mass is real tolerance "default_mass";                                -- [kg]
  subtype stiffness is real tolerance "default_stiffness";                      -- [N/m]
  subtype damping is real tolerance "default_damping";                          -- [N*s/m]
  subtype angle is real tolerance "default_angle";                              -- [rad]
  subtype torque is real tolerance "default_torque";                            -- [N*m]
  subtype angular_velocity is real tolerance "default_angular_velocity";        -- [rad/s]
  subtype angular_acceleration is real tolerance "default_angular_acceleration";-- [rad/s**2]
  subtype moment_inertia is real tolerance "default_moment_inertia";            -- [kg*m**2]
  subtype angular_stiffness is real tolerance "default_angular_stiffness";      -- [N*m/rad]
  subtype angular_damping is real tolerance "default_angular_damping";          -- [N*m*s/rad]

  nature translational is displacement across force through translational_ref reference;
  nature translational_velocity is velocity across force through translational_velocity_ref reference;
  nature rotational is angle across torque through rotational_ref reference;
  nature rotational_velocity is angular_velocity across torque through rotational_velocity_ref reference;
  subnature translational_v is translational_velocity;
  subnature rotational_v is rotational_velocity;
end package mechanical_systems;
