-- IEEE.MECHANICAL_SYSTEMS, as in IEEE Std 1076.1.1, written for tools that do not ship it.
-- Compile into library IEEE. The names are the standard's; the comments are this project's.
--
-- Sign convention (all mechanical natures, the same as electrical): across = position/velocity of the
-- plus terminal relative to the minus terminal; through = force/torque flowing from the plus terminal
-- through the model to the minus terminal, i.e. the force/torque the model takes from the plus terminal.
-- across'dot * through is the power the model absorbs [W]. A source that pushes a terminal forward has a
-- negative through quantity there.
library ieee;
use ieee.fundamental_constants.all;

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
  subtype momentum is real tolerance "default_momentum";                        -- [kg*m/s]
  subtype angular_momentum is real tolerance "default_angular_momentum";        -- [kg*m**2/s]

  attribute unit of displacement : subtype is "meter";
  attribute unit of force : subtype is "newton";
  attribute unit of velocity : subtype is "meter/second";
  attribute unit of acceleration : subtype is "meter/second^2";
  attribute unit of mass : subtype is "kilogram";
  attribute unit of stiffness : subtype is "newton/meter";
  attribute unit of damping : subtype is "newton*second/meter";
  attribute unit of momentum : subtype is "kilogram*meter/second";
  attribute unit of angle : subtype is "radian";
  attribute unit of torque : subtype is "newton*meter";
  attribute unit of angular_velocity : subtype is "radian/second";
  attribute unit of angular_acceleration : subtype is "radian/second^2";
  attribute unit of moment_inertia : subtype is "kilogram*meter^2";
  attribute unit of angular_momentum : subtype is "kilogram*meter^2/second";
  attribute unit of angular_stiffness : subtype is "newton*meter/radian";
  attribute unit of angular_damping : subtype is "newton*meter*second/radian";
  attribute symbol of displacement : subtype is "m";
  attribute symbol of force : subtype is "N";
  attribute symbol of velocity : subtype is "m/s";
  attribute symbol of acceleration : subtype is "m/s^2";
  attribute symbol of mass : subtype is "kg";
  attribute symbol of stiffness : subtype is "N/m";
  attribute symbol of damping : subtype is "N*s/m";
  attribute symbol of momentum : subtype is "kg*m/s";
  attribute symbol of angle : subtype is "rad";
  attribute symbol of torque : subtype is "N*m";
  attribute symbol of angular_velocity : subtype is "rad/s";
  attribute symbol of angular_acceleration : subtype is "rad/s^2";
  attribute symbol of moment_inertia : subtype is "kg*m^2";
  attribute symbol of angular_momentum : subtype is "kg*m^2/s";
  attribute symbol of angular_stiffness : subtype is "N*m/rad";
  attribute symbol of angular_damping : subtype is "N*m*s/rad";

  nature translational is displacement across force through translational_ref reference;
  nature translational_velocity is velocity across force through translational_velocity_ref reference;
  nature rotational is angle across torque through rotational_ref reference;
  nature rotational_velocity is angular_velocity across torque through rotational_velocity_ref reference;
  subnature translational_v is translational_velocity;
  subnature rotational_v is rotational_velocity;
  nature translational_vector is array (natural range <>) of translational;
  nature translational_velocity_vector is array (natural range <>) of translational_velocity;
  nature rotational_vector is array (natural range <>) of rotational;
  nature rotational_velocity_vector is array (natural range <>) of rotational_velocity;

  -- The standard declares the vector subtypes of the across and through types as n_vector'across and
  -- n_vector'through; GHDL 5 stops on those with an internal error, so they are written as the real_vector
  -- subtypes they denote (same tolerance group).
  subtype displacement_vector is real_vector tolerance "default_displacement";  -- [m]
  subtype force_vector is real_vector tolerance "default_force";  -- [N]
  subtype velocity_vector is real_vector tolerance "default_velocity";  -- [m/s]
  subtype force_velocity_vector is real_vector tolerance "default_force";  -- [N]
  subtype angle_vector is real_vector tolerance "default_angle";  -- [rad]
  subtype torque_vector is real_vector tolerance "default_torque";  -- [N*m]
  subtype angular_velocity_vector is real_vector tolerance "default_angular_velocity";  -- [rad/s]
  subtype torque_velocity_vector is real_vector tolerance "default_torque";  -- [N*m]

  subtype acceleration_vector is real_vector tolerance "default_acceleration";  -- [m/s**2]
  subtype mass_vector is real_vector tolerance "default_mass";  -- [kg]
  subtype stiffness_vector is real_vector tolerance "default_stiffness";  -- [N/m]
  subtype damping_vector is real_vector tolerance "default_damping";  -- [N*s/m]
  subtype momentum_vector is real_vector tolerance "default_momentum";  -- [kg*m/s]
  subtype angular_acceleration_vector is real_vector tolerance "default_angular_acceleration";  -- [rad/s**2]
  subtype moment_inertia_vector is real_vector tolerance "default_moment_inertia";  -- [kg*m**2]
  subtype angular_momentum_vector is real_vector tolerance "default_angular_momentum";  -- [kg*m**2/s]
  subtype angular_stiffness_vector is real_vector tolerance "default_angular_stiffness";  -- [N*m/rad]
  subtype angular_damping_vector is real_vector tolerance "default_angular_damping";  -- [N*m*s/rad]

  alias anchor is translational_ref;
  alias translational_v_ref is translational_velocity_ref;
  alias rotational_v_ref is rotational_velocity_ref;
end package mechanical_systems;
