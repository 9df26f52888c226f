-- antipinch: the anti-pinch algorithm of ecu_software behind the interface an algorithm implements
-- (docs/anti-pinch.md, "Algorithm interface"). The ECU software keeps the position, the run state, the relays
-- and the reversal; it calls the algorithm at the start of every run (ap_start), at every Hall-A edge in the
-- run's direction (ap_edge, which answers whether there is a pinch) and when a run up ends in a stall at the
-- top (ap_top); ap_load tells what the algorithm last compared, for plots. The algorithm's state is a record the
-- ECU holds for it (ap_memory) and passes in and out, so that the package needs no shared variable; ap_config
-- carries the ECU's generics the algorithm reads.
--
-- The algorithm (docs/anti-pinch.md, "Anti-pinch"): at every Hall-A edge of a run up, the armature speed n
-- over the last revolution (4 edges, timed with the time register) is compared with the no-load speed at
-- the measured supply voltage:
--   deficit = rpm_per_volt*U_supply - n                                        [rpm]
-- For a DC motor the deficit is proportional to the load torque and independent of the voltage (the
-- speed-torque lines of a motor are parallel, Eq. 4.1), so one reference learned at 13 V serves 9 .. 16 V.
-- The reference is the deficit over the position in bins of edges_per_bin edges, interpolated linearly
-- between bin centres. It is learned in the normalization run (the first learned value of a bin is taken
-- as it is) and refined by every later run up that ends in a stall within the no-pinch zone below the top
-- (ref += (mean - ref)/2**learn_shift); runs that end otherwise are not learned. Only samples taken
-- start_us or later after the start are learned (the start-up oscillation of the cable loop, 4.2.2, is a
-- function of time, not of position); below the lowest learned bin its value is used. A pinch is
--   deficit - reference(position) > threshold_rpm + startup_rpm*(start_us - t_run)/start_us
-- (the second term only while t_run < start_us), tested from the (blank_edges + 1)-th edge of the run on
-- and only while the ECU is normalized and the position is more than zone_edges below the top.
--
-- Two implementations of the same algorithm: this package's VHDL, and vhdl/digital/antipinch.c, the example of
-- an algorithm in C compiled into the loop (ap_config.algorithm = 1, ecu_software's generic `algorithm`: GHDL's
-- VHPIDIRECT calls the C functions wrsim_ap_start, wrsim_ap_edge and wrsim_ap_top). wrsim compiles the C file
-- named below and links it into every digital unit that uses this package:
-- c source: antipinch.c
--
-- Algorithm 2, the same with the supply filtered: the speed follows the supply with the drive's mechanical time
-- constant tau = J*ra/(ke*kt) (Eq. 4.1), so a supply step makes the raw deficit jump by rpm_per_volt*dU until
-- the speed catches up: a dip from 13 to 9 V for 10 ms, as at an engine crank, reverses the window on the way
-- back up (compliance bench, run supply_dip). Algorithm 2 takes the deficit against the supply passed through
-- a first-order filter with that time constant (supply_tau_us), updated at every edge of the run:
--   u_f += (U - u_f)*dt/(tau + dt)          (dt: time since the previous edge of the run; u_f = U at the first)
--
-- Algorithm 3, per edge: the speed over each Hall-A edge (a quarter revolution) instead of a revolution, by the
-- share of its magnet pole (hall_sensor's pole_shares, learned: share += (dt/t_rev - share)/16 at every edge
-- after start_us), against the filtered supply of algorithm 2.
--
-- Algorithm 4, the load observer: for the DC motor with its mechanical time constant tau (Eq. 4.1),
--   tau*dn/dt + n = rpm_per_volt*U - L      (L: the load as a speed deficit, proportional to the load torque)
-- and integrated over the last revolution (the integral of n over one revolution is one revolution):
--   L = rpm_per_volt*mean(U) - 60e6/t_rev - tau*(n_now - n_rev_back)/t_rev
-- with mean(U) the supply averaged over the revolution (trapezoid between edges), n the per-edge speed of
-- algorithm 3 and tau = supply_tau_us. L is the deficit the baseline would read once the speed has settled, so
-- the same reference and threshold serve; it sees a load without the drive's lag of tau. A supply step shows
-- in L until the per-edge speeds have followed it, so the threshold rises by rpm_per_volt*|U - u_f| (u_f:
-- algorithm 2's filtered supply).
--
-- Algorithm 5, the observer with a settled reference: algorithm 4, but the value a run teaches a bin is the
-- deficit averaged over one period of the glass swinging on its cable springs (mode_us, centred on the edge:
-- the run is buffered, so the mean needs no delay). That swing is a function of time, not of position: a learning
-- run that swings (a start, a judder of the seals) taught algorithm 4's bins of edges_per_bin edges the phase it
-- happened to be in, a pattern over position that a later run at another speed does not repeat. And a swing
-- (a rough road shaking the door) need not be even about the run's level: the threshold rises by the larger of
-- algorithm 4's term (twice the fall below the level) and the recent drop from a peak, which a pinch, only
-- rising, does not make: peak follows the load up at once and down by 1/64 per edge, swing is the largest
-- peak - load, leaking by 63/64 per edge.
--
-- Algorithm 6, the observer with a rise over one swing: algorithm 5, and a second test that sees an obstacle met
-- while the glass still swings (right after a start, or stick-slipping in its seals). The load above the reference
-- swings with the period mode_us of the glass on its cable springs; a pinch makes it rise. So the load is compared
-- with its own value one period earlier (interpolated between buffered edges), in which an even swing at that
-- period cancels and an obstacle met within the period shows whole, with no lag:
--   rise = r(t) - r(t - mode_us)           (r: deficit - reference(position), the run's level not taken off)
-- pinch also if rise > threshold_rpm + the supply-step term + twice the recent fall of rise (a swing at another
-- period, a rough road, makes rise fall as well: a pinch does not). While the cable winds up after a start the load
-- rises with the motor's travel, not the glass's: rise is taken from one period after the run's first crest (the
-- load risen by threshold_rpm/2 from its lowest so far, then fallen by as much: the glass breaking away) on, and
-- tested once it has run for half the period of the slowest rough road (ap_road_us, 5 Hz), when its leaky minimum
-- has seen a trough of any road's swing.
--
-- Algorithm 7, the current observer (for a speed-controlled drive with current sensing, the PWM ECU): algorithm 6
-- with the load taken from the measured motor current instead of the driving voltage. The motor's torque balance
-- kt*i = T_load + J*dw/dt gives, in the speed-deficit units of the other algorithms (rpm_per_amp = ra/ke, the speed
-- a drive on a voltage source loses per ampere: rpm_per_volt*ra),
--   L = rpm_per_amp*mean(i) - tau*(n_now - n_rev_back)/t_rev      (mean(i): the current over the revolution)
-- mean(i) is the ECU's: the mean of its ADC's conversions over each edge's period (ecu_software integrates the
-- current register), weighted by the periods. Samples of the current at the edges alone miss what it does between
-- them: through a 10 ms supply dip at -40 degC their trapezoid read up to 19 N of load that was not there.
-- Algorithms 4-6 read L from the voltage, rpm_per_volt*mean(U) - n, which holds only with the drive's flux at the
-- value rpm_per_volt was set for: at 85 degC the flux is 22 % lower (wrsim.data.temperature), the voltage-based L
-- carries an error of (1 - ke_hot/ke)*n that changes with the speed, and a speed controller changes the speed
-- along a run (a drive at its duty limit crawling through the top seal reads as a pinch). The current carries kt
-- alone: a temperature scales L (and the learned reference with it) without an offset. A supply step moves the
-- current and the speed together, so the threshold does not rise for one. No current (supply_dv-style -1, or a
-- relay ECU without current sensing): no detection.
--
-- Learned state (docs/anti-pinch.md, "Warm start"): what the algorithm learns and keeps from run to run -- the
-- reference bins (ref, ref_ok; lowest follows from them) and the pole shares of algorithms 3-5 -- is saved as
-- text with ap_save and read back with ap_restore, so that an ECU can power up with the state of an earlier run
-- (ecu_software's learned_file / learned_out). The format, one item per line, fields separated by blanks,
-- blank lines and everything from '#' to the end of a line ignored:
--   wrsim-antipinch-learned 1          header: the format and its version (the first line)
--   algorithm <n>                      the algorithm that learned it (any but 1)
--   edges_per_bin <n>                  [edges] the bin length it was learned with
--   share <s0> <s1> <s2> <s3>          [1/4096 rev] the pole shares (1 .. 4095; optional, 1024 each when left out)
--   bin <k> <ref>                      [rpm] a learned bin (0 .. reference_bins-1, each at most once)
-- The algorithm and edges_per_bin must be the reading ECU's; every other key, a missing key, a file without a bin,
-- a malformed number or text after the values is an error. Only the VHDL algorithms (all but 1) have one: the C
-- twin keeps its memory in antipinch.c, whose interface has no calls to get or set it.
--
-- Limits: at most ap_max_bins reference bins and ap_max_run edges of one run (ecu_software asserts its
-- generics against them); speed resolution 1 us per revolution.
use std.textio.all;

package antipinch is
  constant ap_algorithms : positive := 8;        -- [1] the algorithms this package has: 0 .. 7 (ap_config.algorithm)
  constant ap_no_current : integer := integer'low;  -- current_ma of ap_edge when the ECU measures none
  constant ap_max_bins   : positive := 512;      -- [1] reference bins an algorithm may keep
  constant ap_max_run    : positive := 4096;     -- [edges] edges of one run up it may buffer
  constant ap_max_swing  : positive := 128;      -- [edges] edges algorithm 6 keeps for its rise over one mode_us
  constant ap_road_us    : positive := 200_000;  -- [us] the longest period of a rough road algorithm 6 rides through
                                                 -- (5 Hz, the low end of the road band, docs/anti-pinch.md)

  type ap_ints  is array (natural range <>) of integer;
  type ap_flags is array (natural range <>) of boolean;

  -- The ECU's generics the algorithm reads (ecu_software documents each).
  type ap_config is record
    algorithm      : integer;  -- 0: this package's VHDL, 1: the C functions of antipinch.c (VHPIDIRECT),
                               -- 2: the VHDL with the supply filtered (supply_tau_us), 3: per edge, 4: observer,
                               -- 5: observer with a settled reference (mode_us), 6: 5 and its rise over one
                               -- mode_us
    rpm_per_volt   : integer;  -- [rpm/V] no-load armature speed per volt of supply
    rpm_per_amp    : integer;  -- [rpm/A] algorithm 7: speed deficit per ampere of motor current (ra/ke)
    threshold_rpm  : integer;  -- [rpm] speed deficit above the reference that is a pinch
    startup_rpm    : integer;  -- [rpm] extra threshold at a start, falling linearly to 0
    start_us       : integer;  -- [us] duration of that fall
    blank_edges    : integer;  -- [edges] no detection and no learning after a start
    edges_per_bin  : integer;  -- [edges] length of one bin of the reference
    reference_bins : integer;  -- [1] number of bins (from the top down), <= ap_max_bins
    learn_shift    : integer;  -- [1] a later run up moves the reference by 1/2**learn_shift
    max_run_edges  : integer;  -- [edges] longest run up that is learned, <= ap_max_run
    zone_edges     : integer;  -- [edges] no-pinch zone below the top
    supply_tau_us  : integer;  -- [us] the drive's mechanical time constant J*ra/(ke*kt): algorithms 2-6's supply
                               -- filter, algorithms 4-6's observer
    mode_us        : integer;  -- [us] algorithms 5, 6: period of the glass swinging on its cable springs
  end record;

  -- The algorithm's memory, held by the ECU.
  type ap_memory is record
    ref       : ap_ints(0 to ap_max_bins - 1);   -- [rpm] learned deficit per bin
    ref_ok    : ap_flags(0 to ap_max_bins - 1);
    lowest    : integer;                         -- deepest learned bin (-1: none)
    run_def   : ap_ints(0 to ap_max_run - 1);    -- [rpm] deficit per edge travelled up in this run
    run_ok    : ap_flags(0 to ap_max_run - 1);
    run_t     : ap_ints(0 to ap_max_run - 1);    -- [us] algorithm 5: time of each of those samples
    edge_t    : ap_ints(0 to 3);                 -- [us] captured times of the last 4 run edges
    run_start : integer;                         -- [us] start of the run
    run_pos   : integer;                         -- [edges] position at the start of the run
    u_f       : integer;                         -- [0.1 V / 64] algorithms 2-5: filtered supply (-1: none yet)
    t_last    : integer;                         -- [us] algorithms 2-5: time of the previous edge of the run
    share     : ap_ints(0 to 3);                 -- [1/4096 rev] algorithms 3-5: learned share of each pole
    n_edge    : ap_ints(0 to 3);                 -- [rpm] algorithms 3-5: speed over each of the last 4 edges
    t_prev    : integer;                         -- [us] algorithms 3-5: time of the previous edge of the run
    u_dt      : ap_ints(0 to 3);                 -- [0.1 V*us] algorithms 4, 5: supply x period of each of the last 4
                                                 -- edges
    u_prev    : integer;                         -- [0.1 V] algorithms 4, 5: supply at the previous edge of the run
    i_dt      : ap_ints(0 to 3);                 -- [10 mA*us] algorithm 7: mean current x period of each of the
                                                 -- last 4 edges
    base      : integer;                         -- [rpm/16] algorithms 4, 5: this run's level above the reference
    base_ok   : boolean;                         -- algorithms 4, 5: base taken (the first edge after start_us)
    base_sum  : integer;                         -- [rpm] algorithms 4, 5: sum of the load above the reference ...
    base_n    : integer;                         -- [1] ... over the edges of the second half of start_us
    low       : integer;                         -- [rpm] algorithms 4, 5: leaky minimum of the level-free load
    peak      : integer;                         -- [rpm] algorithm 5: leaky maximum of the level-free load
    swing     : integer;                         -- [rpm] algorithm 5: leaky largest drop from it (-1: none yet)
    shown     : integer;                         -- [rpm] the load above the reference at the last compared edge
                                                 -- (held through the reversal, for plots)
    sw_r      : ap_ints(0 to ap_max_swing - 1);  -- [rpm] algorithm 6: the load above the reference at the run's ...
    sw_t      : ap_ints(0 to ap_max_swing - 1);  -- [us] ... last edges, and their times (a ring)
    sw_n      : integer;                         -- [1] algorithm 6: edges in the ring (ring slot: sw_n mod its size)
    valley    : integer;                         -- [rpm] algorithm 6: the run's lowest load before its first crest
    top_r     : integer;                         -- [rpm] algorithm 6: the highest load since that valley ...
    top_t     : integer;                         -- [us] ... and its time
    crest     : integer;                         -- [us] algorithm 6: the run's first crest (-1: not yet)
    rise_low  : integer;                         -- [rpm] algorithm 6: leaky minimum of rise
    rise_t0   : integer;                         -- [us] algorithm 6: the first edge with a rise (-1: none yet)
  end record;

  constant ap_initial : ap_memory := (ref => (others => 0), ref_ok => (others => false), lowest => -1,
                                      run_def => (others => 0), run_ok => (others => false), run_t => (others => 0),
                                      edge_t => (others => 0), run_start => 0, run_pos => 0, u_f => -1,
                                      t_last => 0, share => (others => 1024), n_edge => (others => 0),
                                      t_prev => 0, u_dt => (others => 0), u_prev => 0, i_dt => (others => 0),
                                      base => 0, base_ok => false, base_sum => 0, base_n => 0, low => 0,
                                      peak => 0, swing => -1, shown => 0, sw_r => (others => 0),
                                      sw_t => (others => 0), sw_n => 0, valley => 0, top_r => 0, top_t => 0,
                                      crest => -1, rise_low => 0, rise_t0 => -1);

  -- A run starts (up, down or a reversal) at time t_us [us] and position pos [edges below the top].
  procedure ap_start(m : inout ap_memory; c : in ap_config; t_us : in natural; pos : in integer);

  -- A Hall-A edge in the run's direction: t_us its captured time, pos the position after it, run_edges the
  -- edges of the run so far (this one included), up = the run goes up, supply_dv the supply voltage [0.1 V]
  -- (-1: unknown; a PWM ECU passes the mean voltage it drives the motor with), current_ma the motor current [mA]
  -- averaged over the time since the previous call of the run (since its start at the first; ap_no_current: not
  -- measured), normalized = the top is known. pinch: reverse now.
  procedure ap_edge(m : inout ap_memory; c : in ap_config; t_us : in natural; pos : in integer;
                    run_edges : in natural; up : in boolean; supply_dv : in integer; current_ma : in integer;
                    normalized : in boolean; pinch : out boolean);

  -- A run up ended in a stall at the top, which is `shift` edges from the run's position scale (the
  -- normalization run: the count at the stall; later runs: 0).
  procedure ap_top(m : inout ap_memory; c : in ap_config; shift : in integer);

  -- Write the learned state of m to f in the format above (the VHDL algorithms: all but 1).
  procedure ap_save(file f : text; m : in ap_memory; c : in ap_config);

  -- Read a learned state written by ap_save from f into m, replacing m's (bins that f does not give are not
  -- learned; the per-run state is left alone). why = null when f is good, else the reason, and n the number of
  -- the line it concerns (why and n are inout: VHDL-93 reads no out parameter).
  procedure ap_restore(file f : text; m : inout ap_memory; c : in ap_config; n : inout natural; why : inout line);

  -- What the algorithm compared with its threshold at the last edge it compared: the load above its reference
  -- [rpm of speed deficit], held until the next (0 before the first). For plots: the ECU divides it by its
  -- rpm_per_newton to an estimated force.
  function ap_load(m : ap_memory; c : ap_config) return integer;
end package antipinch;

package body antipinch is
  constant us_per_min : natural := 60_000_000;

  -- The C implementation (antipinch.c), called through VHPIDIRECT; the bodies below only run if it is missing.
  procedure c_start(t_us, pos, rpm_per_volt, threshold_rpm, startup_rpm, start_us, blank_edges, edges_per_bin,
                    reference_bins, learn_shift, max_run_edges, zone_edges : integer);
  attribute foreign of c_start : procedure is "VHPIDIRECT wrsim_ap_start";
  function c_edge(t_us, pos, run_edges, up, supply_dv, current_ma, normalized : integer) return integer;
  attribute foreign of c_edge : function is "VHPIDIRECT wrsim_ap_edge";
  procedure c_top(shift : integer);
  attribute foreign of c_top : procedure is "VHPIDIRECT wrsim_ap_top";
  function c_load return integer;
  attribute foreign of c_load : function is "VHPIDIRECT wrsim_ap_load";

  procedure c_start(t_us, pos, rpm_per_volt, threshold_rpm, startup_rpm, start_us, blank_edges, edges_per_bin,
                    reference_bins, learn_shift, max_run_edges, zone_edges : integer) is
  begin
    assert false report "antipinch: the C algorithm (antipinch.c) is not linked" severity failure;
  end procedure c_start;

  function c_edge(t_us, pos, run_edges, up, supply_dv, current_ma, normalized : integer) return integer is
  begin
    assert false report "antipinch: the C algorithm (antipinch.c) is not linked" severity failure;
    return 0;
  end function c_edge;

  procedure c_top(shift : integer) is
  begin
    assert false report "antipinch: the C algorithm (antipinch.c) is not linked" severity failure;
  end procedure c_top;

  function c_load return integer is
  begin
    assert false report "antipinch: the C algorithm (antipinch.c) is not linked" severity failure;
    return 0;
  end function c_load;

  function flag(b : boolean) return integer is
  begin
    if b then
      return 1;
    end if;
    return 0;
  end function flag;

  procedure ap_start(m : inout ap_memory; c : in ap_config; t_us : in natural; pos : in integer) is
  begin
    if c.algorithm = 1 then
      c_start(t_us, pos, c.rpm_per_volt, c.threshold_rpm, c.startup_rpm, c.start_us, c.blank_edges, c.edges_per_bin,
              c.reference_bins, c.learn_shift, c.max_run_edges, c.zone_edges);
      return;
    end if;
    m.run_start := t_us;
    m.run_pos := pos;
    m.run_ok := (others => false);
    m.u_f := -1;
    m.base := 0;
    m.base_ok := false;
    m.base_sum := 0;
    m.base_n := 0;
    m.low := 0;
    m.peak := 0;
    m.swing := -1;
    m.sw_n := 0;
    m.crest := -1;
    m.rise_low := 0;
    m.rise_t0 := -1;
  end procedure ap_start;

  -- Reference at position p (edges below the top): linear between the centres of learned bins; below the
  -- lowest learned bin (the start of the learning run, not learned) that bin's value. found = false where no
  -- learned bin covers p.
  procedure lookup(m : in ap_memory; c : in ap_config; p : in integer; found : out boolean;
                   ref_rpm : out integer) is
    variable b   : integer;
    variable off : integer;
  begin
    found := false;
    ref_rpm := 0;
    if p < 0 then
      return;
    end if;
    b := p / c.edges_per_bin;
    if b > m.lowest then
      b := m.lowest;
    end if;
    if b < 0 then
      return;
    end if;
    if not m.ref_ok(b) then
      return;
    end if;
    found := true;
    ref_rpm := m.ref(b);
    off := p - b * c.edges_per_bin - c.edges_per_bin / 2;  -- offset from the centre of bin b [edges]
    if off >= 0 and b < m.lowest then
      if m.ref_ok(b + 1) then
        ref_rpm := m.ref(b) + (m.ref(b + 1) - m.ref(b)) * off / c.edges_per_bin;
      end if;
    elsif off < 0 and b > 0 then
      if m.ref_ok(b - 1) then
        ref_rpm := m.ref(b) + (m.ref(b) - m.ref(b - 1)) * off / c.edges_per_bin;
      end if;
    end if;
  end procedure lookup;

  -- Algorithm 6: buffer r, the load above the reference at this edge (time t_us), and tell its rise over the last
  -- mode_us (ok = false until one period after the run's first crest and ap_road_us/2 more).
  procedure swing_rise(m : inout ap_memory; c : in ap_config; t_us : in integer; r : in integer; ok : out boolean;
                       rise : out integer) is
    variable k, j, older, tb, d : integer;
  begin
    ok := false;
    rise := 0;
    if m.sw_n = 0 or (m.crest < 0 and r < m.valley) then   -- a new lowest load: a crest must rise from here
      m.valley := r;
      m.top_r := r;
      m.top_t := t_us;
    elsif r > m.top_r then
      m.top_r := r;
      m.top_t := t_us;
    elsif m.crest < 0 and m.top_r - m.valley >= c.threshold_rpm / 2 and r <= m.top_r - c.threshold_rpm / 2 then
      m.crest := m.top_t;
    end if;
    m.sw_r(m.sw_n mod ap_max_swing) := r;
    m.sw_t(m.sw_n mod ap_max_swing) := t_us;
    m.sw_n := m.sw_n + 1;
    tb := t_us - c.mode_us;
    if m.crest < 0 or tb < m.crest then
      return;
    end if;
    -- the newest buffered edge at or before tb, and the one after it (in 64 us units: the product stays < 2**31)
    k := m.sw_n - 2;
    while k >= 0 and k > m.sw_n - ap_max_swing and m.sw_t(k mod ap_max_swing) > tb loop
      k := k - 1;
    end loop;
    if k < 0 or k <= m.sw_n - ap_max_swing then
      return;
    end if;
    j := k mod ap_max_swing;
    older := m.sw_r(j) + (m.sw_r((k + 1) mod ap_max_swing) - m.sw_r(j)) * ((tb - m.sw_t(j)) / 64)
             / ((m.sw_t((k + 1) mod ap_max_swing) - m.sw_t(j)) / 64 + 1);
    if m.rise_t0 < 0 then
      m.rise_t0 := t_us;
    end if;
    ok := 2 * (t_us - m.rise_t0) >= ap_road_us;   -- once rise_low has seen a trough of any road's swing
    d := r - older;
    rise := d;
    m.rise_low := m.rise_low * 63 / 64;
    if d < m.rise_low then
      m.rise_low := d;
    end if;
  end procedure swing_rise;

  procedure ap_edge(m : inout ap_memory; c : in ap_config; t_us : in natural; pos : in integer;
                    run_edges : in natural; up : in boolean; supply_dv : in integer; current_ma : in integer;
                    normalized : in boolean; pinch : out boolean) is
    variable slot      : natural;
    variable rpm       : integer;
    variable deficit   : integer;
    variable bound_rpm : integer;
    variable ref_rpm   : integer;
    variable found     : boolean;
    variable dt        : integer;   -- [us] algorithms 3, 4: period of this edge
    variable n         : integer;   -- [rpm] algorithms 3, 4: speed over this edge, corrected for its pole's share
    variable n_back    : integer;   -- [rpm] algorithms 3, 4: the same one revolution (4 edges) back
    variable rev       : integer;   -- [us] time of the last revolution (4 edges)
    variable u16       : integer;   -- [0.1 V / 16] algorithm 4: mean supply over the last revolution
    variable i_mean    : integer;   -- [10 mA] algorithm 7: mean current over the last revolution
    variable known     : boolean;   -- what this algorithm's load needs is measured
    variable step_rpm  : integer;   -- [rpm] algorithms 4-6: the threshold's rise for a supply step
    variable rise      : integer;   -- [rpm] algorithm 6: the load's rise over one mode_us
    variable rise_ok   : boolean;
    variable risen     : boolean;   -- algorithm 6: rise over its bound
  begin
    if c.algorithm = 1 then
      pinch := c_edge(t_us, pos, run_edges, flag(up), supply_dv, current_ma, flag(normalized)) = 1;
      return;
    end if;
    pinch := false;
    slot := run_edges mod 4;
    if c.algorithm >= 2 and supply_dv >= 0 then
      if m.u_f < 0 or t_us - m.t_last >= 8 * c.supply_tau_us then   -- the first edge, or settled
        m.u_f := supply_dv * 64;
      else  -- in 16 us units, so that the product stays below 2**31
        m.u_f := m.u_f + (supply_dv * 64 - m.u_f) * ((t_us - m.t_last) / 16)
                 / ((c.supply_tau_us + t_us - m.t_last) / 16);
      end if;
      m.t_last := t_us;
    end if;
    n := 0;
    n_back := 0;
    if c.algorithm >= 3 and run_edges > 1 then   -- the speed over this edge, by its pole's share
      dt := t_us - m.t_prev;
      if dt < 1 then
        dt := 1;
      end if;
      if run_edges > 4 and t_us - m.run_start >= c.start_us and dt < 100_000 and t_us > m.edge_t(slot) then
        -- learn the pole's share (not from a revolution within one timer tick: a record may hold equal times)
        m.share(pos mod 4) := m.share(pos mod 4) + (dt * 4096 / (t_us - m.edge_t(slot)) - m.share(pos mod 4)) / 16;
      end if;
      n := (us_per_min / 64) * m.share(pos mod 4) / dt / 64;
      if n > 30_000 then
        n := 30_000;
      end if;
      n_back := m.n_edge(slot);
      m.n_edge(slot) := n;
      if dt > 1_000_000 then   -- a second without an edge: a stall, where the deficit means nothing
        dt := 1_000_000;
      end if;
      m.u_dt(slot) := (m.u_prev + supply_dv) * dt / 2;
      if c.algorithm = 7 and current_ma /= ap_no_current then   -- in 10 mA, the period at most 0.1 s: < 2**31
        if dt > 100_000 then
          dt := 100_000;
        end if;
        m.i_dt(slot) := current_ma / 10 * dt;   -- current_ma: the mean over this edge's period
      end if;
    end if;
    m.t_prev := t_us;
    m.u_prev := supply_dv;
    if c.algorithm = 7 then
      known := current_ma /= ap_no_current;
    else
      known := supply_dv >= 0;
    end if;
    if up and run_edges > 4 and known and (c.algorithm < 3 or run_edges > 8) then
      -- edge_t(slot) still holds the time of the edge one revolution back
      rev := t_us - m.edge_t(slot);
      if rev < 1 then   -- a revolution's edges within one timer tick (a record may hold equal times)
        rev := 1;
      end if;
      rpm := us_per_min / rev;
      if c.algorithm = 2 then
        deficit := c.rpm_per_volt * m.u_f / 640 - rpm;
      elsif c.algorithm = 3 then   -- per edge, against the filtered supply
        deficit := c.rpm_per_volt * m.u_f / 640 - n;
      elsif c.algorithm = 7 then   -- the current observer: the revolution's mean current + tau * its deceleration
        if rev > 400_000 then   -- the periods are summed at most 0.1 s each
          i_mean := (m.i_dt(0) + m.i_dt(1) + m.i_dt(2) + m.i_dt(3)) / 400_000;
        else
          i_mean := (m.i_dt(0) + m.i_dt(1) + m.i_dt(2) + m.i_dt(3)) / rev;
        end if;
        deficit := c.rpm_per_amp * i_mean / 100 + (n_back - n) * (c.supply_tau_us / 16) / ((rev + 15) / 16);
      elsif c.algorithm >= 4 then   -- the observer: the revolution's mean deficit + tau * its deceleration
        u16 := (m.u_dt(0) + m.u_dt(1) + m.u_dt(2) + m.u_dt(3)) / ((rev + 15) / 16);   -- [0.1 V / 16]
        deficit := c.rpm_per_volt * u16 / 160 - rpm + (n_back - n) * (c.supply_tau_us / 16) / ((rev + 15) / 16);
      else
        deficit := c.rpm_per_volt * supply_dv / 10 - rpm;
      end if;
      if run_edges > c.blank_edges then
        if t_us - m.run_start >= c.start_us and m.run_pos - pos >= 0 and m.run_pos - pos < c.max_run_edges then
          m.run_def(m.run_pos - pos) := deficit;  -- indexed by the edges travelled up in this run
          m.run_ok(m.run_pos - pos) := true;
          m.run_t(m.run_pos - pos) := t_us;
        end if;
        if normalized and pos > c.zone_edges then
          lookup(m, c, pos, found, ref_rpm);
          bound_rpm := c.threshold_rpm;
          if t_us - m.run_start < c.start_us then  -- in ms steps, so that the product stays an integer
            bound_rpm := bound_rpm + c.startup_rpm * ((c.start_us - (t_us - m.run_start)) / 1000) / (c.start_us / 1000);
          end if;
          risen := false;
          if c.algorithm >= 4 and found then
            -- a supply step the speed has not followed yet (the current follows it with the speed: none for 7)
            step_rpm := 0;
            if c.algorithm /= 7 then
              step_rpm := c.rpm_per_volt * abs(supply_dv * 64 - m.u_f) / 640;
            end if;
            bound_rpm := bound_rpm + step_rpm;
            if c.algorithm >= 6 then
              swing_rise(m, c, t_us, deficit - ref_rpm, rise_ok, rise);
              risen := rise_ok and rise > c.threshold_rpm + step_rpm - 2 * m.rise_low;
            end if;
            -- the run's own level: the mean over the second half of start_us, then followed slowly (seals
            -- colder, wetter or more worn than when the reference was learned shift the whole run; a pinch rises)
            if t_us - m.run_start < c.start_us then
              if 2 * (t_us - m.run_start) >= c.start_us then   -- meanwhile the mean so far is the level
                m.base_sum := m.base_sum + deficit - ref_rpm;
                m.base_n := m.base_n + 1;
                m.base := m.base_sum * 16 / m.base_n;
              end if;
            elsif m.base_ok then
              m.base := m.base + ((deficit - ref_rpm) * 16 - m.base) / 256;
            else
              if m.base_n = 0 then   -- a run that had no edge in the second half of start_us
                m.base := (deficit - ref_rpm) * 16;
              end if;
              m.base_ok := true;
            end if;
            ref_rpm := ref_rpm + m.base / 16;
            -- a load that falls below the run's level is an oscillation (a pinch only rises): a rough road
            -- shakes the glass on its cable springs; the threshold rises by twice the recent fall
            m.low := m.low * 63 / 64;
            if deficit - ref_rpm < m.low then
              m.low := deficit - ref_rpm;
            end if;
            if c.algorithm >= 5 then   -- or by the recent drop from a peak, if larger (an uneven swing)
              if m.swing < 0 then
                m.peak := deficit - ref_rpm;
                m.swing := 0;
              end if;
              m.peak := m.peak + (deficit - ref_rpm - m.peak) / 64;
              if deficit - ref_rpm > m.peak then
                m.peak := deficit - ref_rpm;
              end if;
              m.swing := m.swing * 63 / 64;
              if m.peak - (deficit - ref_rpm) > m.swing then
                m.swing := m.peak - (deficit - ref_rpm);
              end if;
            end if;
            if c.algorithm >= 5 and m.swing > -2 * m.low then
              bound_rpm := bound_rpm + m.swing;
            else
              bound_rpm := bound_rpm - 2 * m.low;
            end if;
          end if;
          pinch := found and (deficit - ref_rpm > bound_rpm or risen);
          if found then
            m.shown := deficit - ref_rpm;
          end if;
        end if;
      end if;
    end if;
    m.edge_t(slot) := t_us;
  end procedure ap_edge;

  function ap_load(m : ap_memory; c : ap_config) return integer is
  begin
    if c.algorithm = 1 then
      return c_load;
    end if;
    return m.shown;
  end function ap_load;

  procedure ap_top(m : inout ap_memory; c : in ap_config; shift : in integer) is
    variable sums   : ap_ints(0 to ap_max_bins - 1) := (others => 0);
    variable counts : ap_ints(0 to ap_max_bins - 1) := (others => 0);
    variable p, b, mean : integer;
    variable value      : integer;   -- [rpm] what sample r teaches its bin
    variable sum, n, j  : integer;
  begin
    if c.algorithm = 1 then
      c_top(shift);
      return;
    end if;
    for r in 0 to c.max_run_edges - 1 loop
      if m.run_ok(r) then
        p := m.run_pos - r - shift;
        if p >= 0 and p < c.reference_bins * c.edges_per_bin then
          value := m.run_def(r);
          if c.algorithm >= 5 then   -- the mean of the samples within mode_us/2 of this one (samples are in time order)
            sum := 0;
            n := 0;
            j := r;
            while j > 0 and m.run_ok(j - 1) and 2 * (m.run_t(r) - m.run_t(j - 1)) <= c.mode_us loop
              j := j - 1;
            end loop;
            while j < c.max_run_edges and m.run_ok(j) and 2 * (m.run_t(j) - m.run_t(r)) <= c.mode_us loop
              sum := sum + m.run_def(j);
              n := n + 1;
              j := j + 1;
            end loop;
            value := sum / n;
          end if;
          b := p / c.edges_per_bin;
          sums(b) := sums(b) + value;
          counts(b) := counts(b) + 1;
        end if;
      end if;
    end loop;
    for k in 0 to c.reference_bins - 1 loop
      if counts(k) > 0 then
        mean := sums(k) / counts(k);
        if m.ref_ok(k) then
          m.ref(k) := m.ref(k) + (mean - m.ref(k)) / 2 ** c.learn_shift;
        else
          m.ref(k) := mean;
          m.ref_ok(k) := true;
        end if;
        if k > m.lowest then
          m.lowest := k;
        end if;
      end if;
    end loop;
  end procedure ap_top;
  constant learned_header : string := "wrsim-antipinch-learned";   -- the format's name (ap_save, ap_restore) ...
  constant learned_version : integer := 1;                          -- ... and version

  procedure ap_save(file f : text; m : in ap_memory; c : in ap_config) is
    variable l : line;
  begin
    write(l, learned_header & " ");
    write(l, learned_version);
    writeline(f, l);
    write(l, string'("algorithm "));
    write(l, c.algorithm);
    writeline(f, l);
    write(l, string'("edges_per_bin "));
    write(l, c.edges_per_bin);
    writeline(f, l);
    write(l, string'("share"));
    for k in 0 to 3 loop
      write(l, ' ');
      write(l, m.share(k));
    end loop;
    writeline(f, l);
    for k in 0 to c.reference_bins - 1 loop
      if m.ref_ok(k) then
        write(l, string'("bin "));
        write(l, k);
        write(l, ' ');
        write(l, m.ref(k));
        writeline(f, l);
      end if;
    end loop;
  end procedure ap_save;

  -- The next word of l (characters up to a blank), "" at the end of l.
  procedure read_word(l : inout line; word : inout line) is
    variable ch : character;
  begin
    deallocate(word);
    word := new string'("");
    while l'length > 0 and (l(l'left) = ' ' or l(l'left) = HT or l(l'left) = CR) loop
      read(l, ch);
    end loop;
    while l'length > 0 and l(l'left) /= ' ' and l(l'left) /= HT and l(l'left) /= CR loop
      read(l, ch);
      write(word, ch);
    end loop;
  end procedure read_word;

  -- The next field of l as an integer: ok = false when it is not one (a number must end at a blank).
  procedure read_int(l : inout line; value : inout integer; ok : inout boolean) is
    variable word : line;
    variable good : boolean;
  begin
    read_word(l, word);
    ok := false;
    if word'length > 0 then
      read(word, value, good);
      ok := good and word'length = 0;
    end if;
    deallocate(word);
  end procedure read_int;

  -- How a line with key `key` is written (for the error message of a malformed one).
  function learned_form(key : string) return string is
  begin
    if key = "share" then
      return "share <s0> <s1> <s2> <s3>";
    elsif key = "bin" then
      return "bin <k> <ref>";
    end if;
    return key & " <integer>";
  end function learned_form;

  procedure ap_restore(file f : text; m : inout ap_memory; c : in ap_config; n : inout natural; why : inout line) is
    variable raw, l, key : line;
    variable ok          : boolean;
    variable k, value    : integer;
    variable cut         : natural;
    variable seen_alg    : boolean := false;
    variable seen_epb    : boolean := false;
    variable seen        : ap_flags(0 to ap_max_bins - 1) := (others => false);
    variable share       : ap_ints(0 to 3);
  begin
    why := null;
    n := 1;
    m.ref := (others => 0);
    m.ref_ok := (others => false);
    m.lowest := -1;
    if endfile(f) then
      why := new string'("empty file, expected the header '" & learned_header & " 1'");
      return;
    end if;
    readline(f, l);
    read_word(l, key);
    read_int(l, value, ok);
    if key.all /= learned_header or not ok then
      why := new string'("expected the header '" & learned_header & " 1'");
    elsif value /= learned_version then
      why := new string'("format version " & integer'image(value) & ", this ECU reads version 1");
    else
      read_word(l, key);
      if key'length > 0 then
        why := new string'("unexpected text '" & key.all & "' after the header");
      end if;
    end if;
    deallocate(l);
    while why = null and not endfile(f) loop
      readline(f, raw);
      n := n + 1;
      cut := 0;
      for j in 1 to raw'length loop   -- a comment starts at the first '#'
        if cut = 0 and raw(raw'low + j - 1) = '#' then
          cut := j;
        end if;
      end loop;
      if cut > 0 then
        l := new string'(raw(raw'low to raw'low + cut - 2));
      else
        l := new string'(raw.all);
      end if;
      deallocate(raw);
      read_word(l, key);
      ok := true;
      if key.all = "" then
        null;
      elsif key.all = "algorithm" then
        read_int(l, value, ok);
        if ok and value /= c.algorithm then
          why := new string'("learned by algorithm " & integer'image(value) & ", the ECU runs algorithm "
                             & integer'image(c.algorithm));
        end if;
        seen_alg := true;
      elsif key.all = "edges_per_bin" then
        read_int(l, value, ok);
        if ok and value /= c.edges_per_bin then
          why := new string'("learned with edges_per_bin " & integer'image(value) & ", the ECU has "
                             & integer'image(c.edges_per_bin));
        end if;
        seen_epb := true;
      elsif key.all = "share" then
        for j in 0 to 3 loop
          if ok then
            read_int(l, share(j), ok);
          end if;
          if ok and (share(j) < 1 or share(j) > 4095) then
            why := new string'("a pole share must be in 1 .. 4095 (1/4096 rev)");
          end if;
        end loop;
        if ok and why = null then
          m.share := share;
        end if;
      elsif key.all = "bin" then
        read_int(l, k, ok);
        if ok then
          read_int(l, value, ok);
        end if;
        if ok and (k < 0 or k >= c.reference_bins) then
          why := new string'("bin " & integer'image(k) & " outside 0 .. " & integer'image(c.reference_bins - 1)
                             & " (the ECU's reference_bins)");
        elsif ok and seen(k) then
          why := new string'("bin " & integer'image(k) & " given twice");
        elsif ok then
          seen(k) := true;
          m.ref(k) := value;
          m.ref_ok(k) := true;
          if k > m.lowest then
            m.lowest := k;
          end if;
        end if;
      else
        why := new string'("unknown key '" & key.all & "', expected algorithm, edges_per_bin, share or bin");
      end if;
      if not ok then
        why := new string'("malformed line, expected: " & learned_form(key.all));
      elsif why = null then
        read_word(l, key);
        if key'length > 0 then
          why := new string'("unexpected text '" & key.all & "' after the values");
        end if;
      end if;
      deallocate(l);
    end loop;
    if why = null then
      if not seen_alg then
        why := new string'("no 'algorithm' line");
      elsif not seen_epb then
        why := new string'("no 'edges_per_bin' line");
      elsif m.lowest < 0 then
        why := new string'("no learned bin");
      end if;
    end if;
    deallocate(key);
  end procedure ap_restore;
end package body antipinch;
