library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;
use work.wr_params.all;

-- door_disturbance: what the door does to the glass on a closing without an obstacle, for counting the false
-- reversals of an anti-pinch algorithm (docs/anti-pinch.md, "Disturbances"). From t_on on:
--   rough road  the door moves vertically with the acceleration a(t) = accel*sin(2*pi*frequency*(t - t_on)).
--               Seen from the door (the frame the glass position is measured in) the glass feels the inertial
--               force -glass_mass*a(t): the base excitation of a mass on a spring, the two-mass system of
--               thesis 3.1 with the door as the excited mass and the glass on its cable springs as the other;
--   random road with lines > 0: a(t) is a random acceleration of rms `accel` with a flat spectrum from
--               `frequency` to `band_high` (a road's broadband shaking as the body passes it on, as random-vibration
--               tests specify it), the sum of `lines` sinusoids of equal amplitude accel*sqrt(2/lines), line k at a
--               random frequency within the k-th of `lines` equal parts of the band, with a random phase (random-
--               phase multisine); `seed` draws the frequencies and phases (another seed, another road):
--                 a(t) = accel*sqrt(2/lines)*sum_k sin(2*pi*f_k*(t - t_on) + 2*pi*v_k),
--                 f_k = frequency + (band_high - frequency)*(k - 1 + u_k)/lines,
--               u_k, v_k in [0, 1): the fractional parts of n/golden ratio and n**2*(sqrt(2) - 1), n = k + lines*seed
--               (Weyl sequences, evenly spread; the phases quadratic in k, since phases linear in k would line the
--               sinusoids up into a pulse: the crest factor stays that of a random multisine, about 3-4);
--   seals       the seals grip more (cold rubber) or less (wet or worn seals) than when the ECU learned its
--               reference: an extra Coulomb friction `friction` against the glass velocity (< 0: less friction;
--               keep |friction| below the seal friction of the door, 15 N at the bottom in rail_wr_8p5nm).
-- Before t_on the element takes no force, so the normalization learns the undisturbed door.
--
-- Equations (t >= t_on):
--   force == glass_mass*a(now) + friction*smooth_sign(v, v_threshold)
--
-- Sign convention (passive, IEEE 1076.1.1, translational_v): v = glass velocity against the door frame [m/s]
-- (positive up); force = force the element takes from the glass [N] (> 0: it pushes the glass down).
--
-- Generics: glass_mass (the door's glass, 2.55 kg in rail_wr_8p5nm), accel [m/s**2] (the sinusoid's amplitude, or
-- the random road's rms), frequency [Hz] (the sinusoid's, or the band's lower edge), band_high [Hz], lines, seed,
-- friction [N], t_on [s], v_threshold [m/s] (as seal_friction).
-- Limits: a rigid door (its own modes are not modelled), a flat band of at most 40 lines (the spectrum of a road
-- class passed through a body and its suspension is the user's choice of band and rms), the friction change the
-- same along the whole stroke. Switched on at t_on with the glass at rest: the sinusoid and the friction start
-- from 0, the random road (random phases) from its value at t_on.
entity door_disturbance is
  generic (
    glass_mass  : mass         := door_disturbance_glass_mass;    -- mass of the glass the door carries
    accel       : acceleration := door_disturbance_accel;         -- amplitude of the door's vertical acceleration
    frequency   : real         := door_disturbance_frequency;     -- [Hz] frequency of that acceleration
    band_high   : real         := door_disturbance_band_high;     -- [Hz] a random road: the band's upper edge
    lines       : natural      := door_disturbance_lines;         -- [1] a random road: its sinusoids (0: one sinusoid)
    seed        : natural      := door_disturbance_seed;          -- [1] a random road: draws its frequencies and phases
    friction    : force        := door_disturbance_friction;      -- extra seal friction against the glass velocity (< 0: less)
    t_on        : real         := door_disturbance_t_on;          -- [s] the disturbance starts
    v_threshold : velocity     := door_disturbance_v_threshold);  -- speed below which sgn(v) is linear
  port (
    terminal glass, frame : translational_v);  -- glass edge, door frame
end entity door_disturbance;

architecture behavioral of door_disturbance is
  quantity v across force through glass to frame;  -- glass velocity [m/s], force [N] taken from the glass

  -- the door's acceleration t [s] after t_on per unit of accel: the sinusoid, or the random road
  function shaking(t : real) return real is
    variable sum, u, w : real := 0.0;
  begin
    if lines = 0 then
      return sin(math_2_pi * frequency * t);
    end if;
    for k in 1 to lines loop
      u := real(k + lines * seed) * 0.6180339887498949;
      w := real(k + lines * seed) ** 2 * 0.4142135623730950;
      sum := sum + sin(math_2_pi * (frequency + (band_high - frequency) * (real(k - 1) + u - floor(u)) / real(lines)) * t
                       + math_2_pi * (w - floor(w)));
    end loop;
    return sqrt(2.0 / real(lines)) * sum;
  end function shaking;
begin
  assert glass_mass > 0.0 report "door_disturbance: glass_mass must be > 0" severity failure;
  assert frequency > 0.0 report "door_disturbance: frequency must be > 0" severity failure;
  assert lines = 0 or (lines <= 40 and band_high > frequency)
    report "door_disturbance: a random road needs lines <= 40 and band_high > frequency" severity failure;
  assert v_threshold > 0.0 and v_threshold <= 1.0e-3
    report "door_disturbance: v_threshold must be in (0, 1e-3] m/s" severity failure;
  if now >= t_on use
    force == glass_mass * accel * shaking(now - t_on) + friction * smooth_sign(v, v_threshold);
  else
    force == 0.0;
  end use;
end architecture behavioral;
