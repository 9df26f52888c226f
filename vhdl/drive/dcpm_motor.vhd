library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use work.wr_common.all;
use work.wr_params.all;

-- dcpm_motor: DC permanent-magnet brush motor of the window-regulator drive (thesis 4.1.1, Eq. 4.1,
-- Table 4.1; structure and initial conditions as the thesis's own VHDL-AMS model in Appendix A).
--
-- Equations (thesis Eq. 4.1, written in this library's passive sign convention):
--   4.1a  U_a = R_a*i_a + L_a*di_a/dt + k_e*omega_a
--           ua == ra*ia + laa*ia_dot + ke*omega
--   4.1b  k_t*i_a = M_c + Visc*omega_a + J_a*domega_a/dt + M_la
--           kt*ia == mc*smooth_sign(omega, omega_threshold) + visc*omega + j*alpha - torque
--         with torque = -M_la (see the sign convention below). The Coulomb term M_c of Eq. 4.1b is
--         written as mc*smooth_sign(omega) so that it opposes the rotation in both directions and
--         stays continuous at standstill (thesis 4.1.2.4: linear below the velocity threshold).
--   kinematics: omega'dot == alpha, ia'dot == ia_dot, angle = angle0 + integral of omega;
--   speed_rpm = omega*60/(2*pi).
--
-- Sign convention (IEEE 1076.1.1, passive):
--   ua = v(p) - v(n); ia = current flowing into p, through the winding, out of n. Motoring: ua > 0, ia > 0.
--   omega = shaft speed against the housing (reference, rotational_v: speed is the across quantity, so no
--   speed is ever the derivative of a large angle); torque = torque the motor TAKES FROM its shaft
--   terminal. A motor driving a load delivers M_la to the shaft, so torque = -M_la < 0 in motoring.
--   Appendix A writes `kt*ia == j*acc + trq_armature`, i.e. its trq_armature is the delivered torque
--   M_la (the opposite sign); this model follows the library convention instead.
--
-- Initial conditions (Appendix A): in the quiescent domain (DC operating point) ia and omega are held at
-- ia0 and omega0; from the first time step on the derivative relations apply. Setting ia0 or omega0 to
-- real'low (Appendix A's guard) drops that condition: the derivative relation then also holds at the DC
-- point (derivative = 0), i.e. the motor starts from the steady state for the load present at t = 0.
-- The angle (an observable: the Hall sensor integrates the same speed) starts at angle0.
--
-- Generics: ke, kt, ra, laa, j, visc, mc (Table 4.1), omega_threshold (smoothing of the Coulomb term),
-- ia0, angle0, omega0 (initial conditions). Defaults are Appendix A's example values; parameter sets
-- (params/*) replace them.
-- Limits: linear magnetics, constant parameters (no temperature, no brush-resistance change, no
-- commutation ripple, thesis 4.1.1.4); ra, laa, j must be > 0 (laa = 0 would leave ia_dot undetermined).
entity dcpm_motor is
  generic (
    ke              : real             := dcpm_motor_ke;               -- [V*s/rad] back-EMF constant k_e
    kt              : real             := dcpm_motor_kt;               -- [N*m/A] torque constant k_t
    ra              : resistance       := dcpm_motor_ra;               -- effective armature resistance R_a (winding, brushes, commutator)
    laa             : inductance       := dcpm_motor_laa;              -- effective armature inductance L_a
    j               : moment_inertia   := dcpm_motor_j;                -- effective rotor inertia J_a
    visc            : angular_damping  := dcpm_motor_visc;             -- viscous friction coefficient Visc
    mc              : torque           := dcpm_motor_mc;               -- Coulomb friction torque M_c (bearings, brushes)
    omega_threshold : angular_velocity := dcpm_motor_omega_threshold;  -- speed below which the Coulomb torque is linear in omega
    ia0             : current          := dcpm_motor_ia0;              -- armature current at the DC operating point (real'low: free)
    angle0          : angle            := dcpm_motor_angle0;           -- shaft angle at t = 0
    omega0          : angular_velocity := dcpm_motor_omega0);          -- shaft speed at the DC operating point (real'low: free)
  port (
    terminal p, n  : electrical;   -- motor electrodes (plus, minus)
    terminal shaft : rotational_v);  -- armature shaft
end entity dcpm_motor;

architecture simple of dcpm_motor is
  -- U_a [V] across p-n and i_a [A] from p through the winding to n
  quantity ua across ia through p to n;
  -- armature speed omega_a [rad/s] and the torque [N*m] the motor takes from the shaft (= -M_la)
  quantity omega across torque through shaft;
  quantity angle     : real;  -- [rad] armature angle against the housing
  quantity alpha     : angular_acceleration;  -- armature angular acceleration domega_a/dt
  quantity ia_dot    : real;  -- [A/s] armature current derivative di_a/dt
  quantity speed_rpm : real;  -- [rpm] armature speed in revolutions per minute
begin
  assert ke > 0.0 report "dcpm_motor: ke must be > 0" severity failure;
  assert kt > 0.0 report "dcpm_motor: kt must be > 0" severity failure;
  assert ra > 0.0 report "dcpm_motor: ra must be > 0" severity failure;
  assert laa > 0.0 report "dcpm_motor: laa must be > 0" severity failure;
  assert j > 0.0 report "dcpm_motor: j must be > 0" severity failure;
  assert visc >= 0.0 report "dcpm_motor: visc must be >= 0" severity failure;
  assert mc >= 0.0 report "dcpm_motor: mc must be >= 0" severity failure;
  assert omega_threshold > 0.0 report "dcpm_motor: omega_threshold must be > 0" severity failure;

  -- Eq. 4.1a: electrical balance (Kirchhoff's voltage law).
  ua == ra * ia + laa * ia_dot + ke * omega;

  -- Eq. 4.1b: mechanical balance; torque = -M_la (passive convention).
  kt * ia == mc * smooth_sign(omega, omega_threshold) + visc * omega + j * alpha - torque;

  -- Initial conditions and state derivatives (Appendix A).
  if domain = quiescent_domain and ia0 /= real'low use
    ia == ia0;
  else
    ia'dot == ia_dot;
  end use;

  if domain = quiescent_domain and omega0 /= real'low use
    omega == omega0;
  else
    omega'dot == alpha;
  end use;

  angle == angle0 + omega'integ;
  speed_rpm == omega * rpm_per_radps;
end architecture simple;
