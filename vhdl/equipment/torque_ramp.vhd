library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_params.all;

-- torque_ramp: servo brake of the motor and drive test stands (thesis 4.1.1.4 step 3, Eq. 4.4d: the load
-- torque rises linearly, 0 -> 0.5 N*m in 3 s for the motor; 4.1.4.2: about 2 s up to stall for the drive).
--
-- Equations:
--   load_torque = torque_end * clip((t - t_start)/ramp_time, 0, 1)
--     load_torque == torque_end * realmin(1.0, realmax(0.0, (now - t_start) / ramp_time))
--   torque == direction * load_torque
--
-- Sign convention (passive, IEEE 1076.1.1, rotational_v): omega = shaft speed [rad/s]; torque = torque the brake takes
-- from the shaft [N*m]. With direction = sign of the braked rotation, the brake takes torque in the
-- direction of rotation, i.e. it opposes it (load on the device under test).
-- The brake is a prescribed torque, not a speed-dependent one: once the ramp exceeds the stall torque of
-- the device under test, it drives the device backwards (motor) or loads the self-locking gear (drive).
-- The characteristic benches therefore evaluate only up to the stall region (working ranges of 4.1.1.4 and
-- 4.1.4.2). The ramp is continuous in value (kinks at t_start and t_start + ramp_time).
--
-- Generics: torque_end (>= 0), ramp_time (> 0), t_start, direction (+1 or -1).
entity torque_ramp is
  generic (
    torque_end : torque := torque_ramp_torque_end;  -- brake torque magnitude at the end of the ramp
    ramp_time  : real   := torque_ramp_ramp_time;   -- [s] duration of the ramp from 0 to torque_end
    t_start    : real   := torque_ramp_t_start;     -- [s] time at which the ramp starts (torque 0 before)
    direction  : real   := torque_ramp_direction);  -- [1] sign of the braked rotation: +1.0 or -1.0
  port (
    terminal shaft : rotational_v);  -- shaft of the device under test
end entity torque_ramp;

architecture behavioral of torque_ramp is
  -- shaft speed [rad/s] and the torque [N*m] the brake takes from the shaft
  quantity omega across torque through shaft;
  quantity load_torque : real;  -- [N*m] magnitude of the brake torque
begin
  assert torque_end >= 0.0 report "torque_ramp: torque_end must be >= 0" severity failure;
  assert ramp_time > 0.0 report "torque_ramp: ramp_time must be > 0" severity failure;
  assert direction = 1.0 or direction = -1.0
    report "torque_ramp: direction must be 1.0 or -1.0" severity failure;

  load_torque == torque_end * realmin(1.0, realmax(0.0, (now - t_start) / ramp_time));
  torque == direction * load_torque;
end architecture behavioral;
