"""Closed-loop window-regulator system benches (thesis 5.1, Fig. 5.1): lab supply, ECU hardware and software,
drive with Hall sensor, single-rail mechanism, door and anti-pinch gauge; the ECU software and the switch are
digital units run by GHDL (testbenches/tb_closed_loop.vhd). Parameter set: params/rail_wr_8p5nm.txt. Switch
sequences: params/sequences/*.txt.

* normalization (5.2.1, Fig. 5.3): up from fully open at 13 V until the ECU is normalized, then down to the
  bottom: normalization after the 500 ms stall, electronic position 0 at the top, the position counting
  opposite to the glass at the ECU's edges_per_m, no Hall edge lost or gained on the way down.

The pinch bench (5.3.2, Fig. 5.11; sequence params/sequences/pinch.txt) is not registered: its runs still
end in ngspice "timestep too small" at some stops of the drive (issue 5).

Step: the ECU measures the armature speed from the times of Hall-A edges; an A->D edge lands on the first
ngspice time point after the crossing, so max_step adds up to max_step of timing error per edge to the
ECU's own clock resolution (100 us). At 5e-5 s the speed over one revolution (about 11 ms at 5500 rpm) is
then known to about 1.4 %."""
from __future__ import annotations

import numpy as np

from ..errors import WrsimError
from ..report import Metric, Plot, Signal
from . import ROOT, Bench, Run, Simulated, metric, resampled

__all__ = ["BENCHES"]

SYSTEM_PARAMS = "rail_wr_8p5nm"
SEQUENCES = ROOT / "params" / "sequences"
_EDGES_PER_M = 2112      # [1/m] ecu_software's default edges_per_m (the bench keeps the default)
_STALL_MS = 500.0        # [ms] ecu_software's stall_time_ms default (5.2.1)


def _sequence(name: str) -> str:
    """Path of a committed switch sequence (it reaches GHDL through the run's args file, case and blanks kept)."""
    return str(SEQUENCES / f"{name}.txt")


def _position(s: Simulated) -> np.ndarray:
    """The ECU's electronic position [edges] (the probe reads the 32-bit vector unsigned)."""
    raw = s.waves["position"]
    return np.where(raw >= 2.0 ** 31, raw - 2.0 ** 32, raw)


def _edge_times(t: np.ndarray, level: np.ndarray) -> np.ndarray:
    return t[np.flatnonzero(np.diff(level) != 0) + 1]


# ------------------------------------------------------------------------------------------------
# normalization (5.2.1, Fig. 5.3)
def _judge_normalization(bench: Bench, sims: list[Simulated], table):
    s = sims[0]
    w, t = s.waves, s.waves.time
    pos, glass, norm = _position(s), w["door.pane.pos"], w["normalized"]
    if not np.any(norm > 0.5):
        raise WrsimError(f"{bench.name}: the ECU never became normalized within {bench.stop} s")
    k_norm = int(np.argmax(norm > 0.5))
    t_norm = float(t[k_norm])
    edges = _edge_times(t, w["hall_a"])
    last_up = float(edges[edges < t_norm].max())
    count_up = -float(pos[k_norm - 1])                     # raw count of the learning run [edges]
    top_glass = float(glass[k_norm])
    after = t > t_norm
    down = after & (w["motor_state"] > 1.5)                # ECU drives down
    if not np.any(down):
        raise WrsimError(f"{bench.name}: the ECU never drove down after the normalization")
    end_down = float(t[down][-1])
    bottom_pos = float(pos[np.searchsorted(t, end_down)])
    bottom_glass = float(glass[np.searchsorted(t, end_down)])
    # travel per edge while the glass moves (exclude the stalls at both ends)
    moving = down & (glass < top_glass - 0.01) & (glass > bottom_glass + 0.01)
    slope = -float(np.polyfit(glass[moving], pos[moving], 1)[0])
    turns = (w["dut.motor.angle"] - w["dut.motor.angle"][k_norm]) / (2.0 * np.pi)
    miscount = float(np.max(np.abs((pos - pos[k_norm])[after] + 4.0 * turns[after])))
    metrics: list[Metric] = [
        metric("normalized after the stall at the top", float(norm[-1] > 0.5), 1.0, 0.0, "1",
               f"ECU normalized = '1' at {t_norm:.3f} s, glass at {top_glass * 1e3:.1f} mm (top frame)"),
        metric("stall time before normalization", (t_norm - last_up) * 1e3, _STALL_MS, 0.2, "ms",
               "from the last Hall-A edge of the run up; ECU clock 0.1 ms"),
        metric("electronic position at the top", float(pos[k_norm]), 0.0, 0.0, "edges",
               f"after normalization; the learning run counted {count_up:.0f} edges up"),
        metric("edges per metre (-d position / d glass, down run)", slope, _EDGES_PER_M, 0.03 * _EDGES_PER_M,
               "1/m", "position counts opposite to the glass (positive downwards); ECU edges_per_m; the cable "
               "springs change the travel per edge with the load by a few %"),
        metric("Hall edges lost or gained on the way down", miscount, 0.0, 1.0, "edges",
               "largest difference between the change of the position and 4 edges per armature revolution "
               f"(Hall A) after the normalization; at the bottom {bottom_pos:.0f} edges vs {count_up:.0f} "
               "counted up: the drum winds the cable loop up at each stall"),
    ]
    grid = np.linspace(0.0, bench.stop, 4001)
    plot = Plot(f"{bench.name}: electronic position and glass position (Fig. 5.3)", Signal("time", "s", grid),
                [Signal("electronic position", "1", np.interp(grid, t, pos))],
                [Signal("glass position", "m", np.interp(grid, t, glass))], [], "position.png")
    signals = resampled(sims, {
        "electronic_position": ("1", _position),
        "glass_position": ("m", lambda x: x.waves["door.pane.pos"]),
        "normalized": ("1", lambda x: x.waves["normalized"]),
        "motor_state": ("1", lambda x: x.waves["motor_state"]),
        "current": ("A", lambda x: x.waves["dut.motor.ia"]),
    }, bench.stop)
    return metrics, [plot], signals


BENCHES: list[Bench] = [
    Bench("normalization", "tb_closed_loop", "closed loop: electronic normalization and the run back down "
          "(thesis 5.2.1, Fig. 5.3)", 8.0, 5e-5,
          (Run("normalization", {"sequence_file": _sequence("normalization")}),), _judge_normalization,
          SYSTEM_PARAMS),
]
