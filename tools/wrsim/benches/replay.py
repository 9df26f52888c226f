"""Record and replay (docs/anti-pinch.md, "Record and replay"): until the ECU reverses, a closing does not depend on
the anti-pinch algorithm, which only sees its inputs (Hall edges, the supply register, the command). `record`
runs scenarios once in closed loop with the reversal held off and keeps the ECU's inputs (ecu_software's
record_out) with the gauge force; `replay` runs the ECU software alone (testbenches/tb_replay.vhd, GHDL, VHDL and C
algorithms alike) on a record and tells where an algorithm detects, in milliseconds instead of a closed-loop run.
A warm-started scenario's record keeps the input record of its normalization run too: replaying that first gives
each algorithm its own learned state, as the closed loop would have."""

from __future__ import annotations

import concurrent.futures
import dataclasses
import hashlib
import inspect
import os
import shutil
import subprocess
import tempfile
import threading
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wrsim import paths
from wrsim.backend.ghdl.build import executable
from wrsim.backend.native import run_child
from wrsim.backend.ngspice import osdi
from wrsim.backend.ngspice.netlist import compiled_default
from wrsim.benches.core import Run, simulate_runs
from wrsim.benches.scenario import ECUS, TESTBENCH, Scenario, concept_over, load_scenario, scenario_params
from wrsim.benches.scenario_run import WarmStart, scenario_bench
from wrsim.data.params import ParamSet, load_params
from wrsim.elab.elaborate import elaborate
from wrsim.elab.generics import top_generics
from wrsim.elab.library import Library, load_library
from wrsim.errors import WrsimError
from wrsim.frontend.lexer import tokenize
from wrsim.runner import Runner

__all__ = [
    "Record",
    "Decision",
    "Check",
    "record",
    "kept_record",
    "record_files",
    "store_record",
    "plant_digest",
    "load_record",
    "find_records",
    "read_inputs",
    "ecu_generics",
    "Replayer",
    "replay_table",
    "against_closed_loop",
]

INPUTS = "inputs.txt"  # the case run's ECU input record in a record folder
LEARNING = "learning.txt"  # the normalization run's (warm starts)
TRACE = "trace.npz"  # time, gauge force and glass position of the recorded run, the warm start's counter
REPLAY_TOP = "tb_replay"
# The anti-pinch algorithm's package: with the reversal held off the plant does not depend on it, so a record stays
# valid when an algorithm changes (the point of replaying); its C twin is linked in by name, not part of the library.
ALGORITHM_PACKAGE = "antipinch.vhd"
_TIMEOUT = 60.0  # [s] one replay (a closing is some 10^3 edges: milliseconds)


@dataclass(frozen=True)
class Record:
    """A scenario run in closed loop with the reversal held off: the ECU's inputs and what the plant did."""

    name: str  # the scenario's name
    folder: Path  # where the files lie
    start_position: int  # [edges] the ECU's counter at a warm start (0: cold)
    time: np.ndarray  # [s]
    force: np.ndarray  # [N] gauge force
    glass: np.ndarray  # [m] glass position

    @property
    def inputs(self) -> Path:
        return self.folder / INPUTS

    @property
    def learning(self) -> Path | None:
        """The normalization run's input record of a warm start (None: the case record starts at power-up)."""
        f = self.folder / LEARNING
        return f if f.is_file() else None

    def force_at(self, t: float) -> float:
        """[N] the recorded gauge force at time `t` [s]."""
        return float(np.interp(t, self.time, self.force))


@dataclass(frozen=True)
class Decision:
    """What an algorithm makes of a record: its first detection (None: none until the record ends)."""

    detected: float | None  # [s]
    position: int | None  # [edges] the ECU's position at the detection


def record(
    scenarios: Sequence[str | Path | Scenario],
    workdir: Path,
    user: Sequence[str | Path] | ParamSet = (),
    runner: Runner | None = None,
    lib: Library | None = None,
) -> list[Record]:
    """Run each scenario (files or loaded) once in closed loop with the ECU's reversal held off and its inputs
    recorded; one folder per scenario under `workdir` (`load_record` reads it back). A record made already from the
    same scenario, sets and model library (the algorithm package aside) is kept, so that an interrupted recording
    resumes and a changed algorithm replays on the records it had. `user`: parameter sets
    over each scenario's, as `wrsim scenario --params`, or the set the scenarios start from (a door of a fleet)."""
    from wrsim.benches.run import simulator

    loaded = [s if isinstance(s, Scenario) else load_scenario(s) for s in scenarios]
    runner = runner or simulator()
    runner.check()
    lib = lib or load_library(paths.LIBRARY)
    held = top_generics(lib, TESTBENCH, {"reverse_on_pinch": False})
    warm = WarmStart(lib, runner, workdir / "learn", record=True)
    base = user if isinstance(user, ParamSet) else scenario_params(user)

    models = plant_digest(lib)

    def one(s: Scenario) -> Record:
        folder = workdir / s.name
        kept = kept_record(s, folder, base, models)
        if kept is not None:
            return kept
        key = _key(s, base, models)
        bench = scenario_bench(s, base, warm)
        (run,) = bench.runs
        inputs = (folder / s.name / INPUTS).resolve()
        recording = Run(run.label, {**run.generics, **held, "record_out": str(inputs)}, run.params)
        bench = dataclasses.replace(bench, runs=(recording,))
        (sim,), _ = simulate_runs(bench, lib, base, runner, folder)
        start = run.generics.get("start_position", 0)
        learned = run.generics.get("learned_file")
        w = sim.waves
        (folder / INPUTS).write_bytes(inputs.read_bytes())
        if learned:
            (folder / LEARNING).write_bytes((Path(str(learned)).parent / INPUTS).read_bytes())
        np.savez_compressed(  # last: a folder with a trace holds a whole record
            folder / "trace.tmp.npz",
            time=w.time,
            force=w["pinch_force"],
            glass=w["plant.door.pane.pos"],
            start_position=int(float(start)),  # type: ignore[arg-type]
            key=key,
        )
        (folder / "trace.tmp.npz").replace(folder / TRACE)
        shutil.rmtree(folder / s.name, ignore_errors=True)  # the run's folder: netlist, waveforms, units (MBs)
        return load_record(folder)

    with concurrent.futures.ThreadPoolExecutor(max_workers=_workers(len(loaded))) as pool:
        return list(pool.map(one, loaded))


def kept_record(s: Scenario, folder: Path, base: ParamSet, models: str) -> Record | None:
    """The record of `s` in `folder` if it was made from the same scenario, the set `base` it starts from and the
    model library of digest `models` (plant_digest); else None (none yet, or a stale one)."""
    if not (folder / TRACE).is_file():
        return None
    with np.load(folder / TRACE) as z:
        if "key" in z and str(z["key"]) == _key(s, base, models):
            return load_record(folder)
    return None


def record_files(scenarios: Sequence[Scenario], base: ParamSet, models: str) -> dict[str, dict[str, bytes]]:
    """Record `scenarios` from the set `base` in a folder of its own and return each record's files by scenario
    name (a Dask task of a fleet: the files travel back to the machine that keeps the records, `store_record`).
    One error if this machine's model library is not the one of digest `models`."""
    lib = load_library(paths.LIBRARY)
    if plant_digest(lib) != models:
        raise WrsimError(
            f"a worker's model library ({paths.LIBRARY}) or its compiled-models setting (WRSIM_COMPILE) differs "
            "from the one the fleet records with: run the workers from the same checkout, with the same setting"
        )
    with tempfile.TemporaryDirectory(prefix="wrsim-record-") as tmp:
        out = {}
        for rec in record(scenarios, Path(tmp), base, lib=lib):
            out[rec.name] = {
                f.name: f.read_bytes() for f in (rec.folder / n for n in (INPUTS, LEARNING, TRACE)) if f.is_file()
            }
        return out


def store_record(folder: Path, files: Mapping[str, bytes]) -> Record:
    """Write the record files `files` (record_files) into `folder`, its trace last (a folder with a trace holds a
    whole record), and read it back."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / TRACE).unlink(missing_ok=True)
    for name, data in files.items():
        if name != TRACE:
            (folder / name).write_bytes(data)
    (folder / "trace.tmp.npz").write_bytes(files[TRACE])
    (folder / "trace.tmp.npz").replace(folder / TRACE)
    return load_record(folder)


def plant_digest(lib: Library) -> str:
    """The digest of what a record depends on in `lib` and the simulator: the tokens of every library file but
    ALGORITHM_PACKAGE, so that comments, layout and the case of names (VHDL's identifiers ignore it) keep the
    records and any other edit does not; the C sources of the simulator's own programs (the crossing driver,
    which times the Hall edges, and the GHDL glue); with compiled models (WRSIM_COMPILE) also the generator of
    the compiled device and its header, so that records made the one way are never read as made the other."""
    h = hashlib.sha256()
    for f in lib.files:
        path = Path(f.path)
        if path.name != ALGORITHM_PACKAGE:
            h.update(f"{path.name}\n".encode())
            for tok in tokenize(path.read_text(encoding="utf-8"), str(path)).tokens:
                h.update(f"{tok.kind} {tok.text}\n".encode())
    for c in sorted(paths.COSIM.glob("*.c")):
        h.update(f"{c.name}\n".encode() + c.read_bytes())
    if compiled_default():
        h.update(b"compiled\n" + inspect.getsource(osdi).encode() + (paths.COSIM / "wrsim_osdi.h").read_bytes())
    return h.hexdigest()


def _key(s: Scenario, base: ParamSet, models: str) -> str:
    """What a record depends on: the scenario's file, its ECU concept and their sets, the set it starts from and the
    user's set over the scenario's own (ParamSet.user), the model library (`models`: its plant_digest)."""
    texts = [s.file.read_bytes(), *(p.read_bytes() for p in s.params)]
    concept = ECUS[s.ecu][1]
    if concept is not None:  # (the relay ECU adds nothing: its records keep the keys they were made with)
        texts += [s.ecu.encode(), concept.read_bytes()]

    def sections(pset: ParamSet | None) -> list | None:
        if pset is None:
            return None
        return sorted(
            (e, sorted((k, repr(p.value), p.unit) for k, p in keys.items())) for e, keys in pset.sections.items()
        )

    return hashlib.sha256(repr((texts, sections(base), sections(base.user), models)).encode()).hexdigest()


def find_records(targets: Sequence[str | Path], files: bool = False) -> list[Record | Path]:
    """The records `targets` name: record folders of `record`, or folders holding them; with `files`, also input
    record files (a real door's, from power-up). One error for a target that holds none."""
    out: list[Record | Path] = []
    for target in map(Path, targets):
        if (target / TRACE).is_file():
            out.append(load_record(target))
        elif target.is_dir():
            found = sorted(p.parent for p in target.glob(f"*/{TRACE}"))
            if not found:
                raise WrsimError(f"{target}: no records in this folder (wrsim record writes them)")
            out.extend(load_record(f) for f in found)
        elif files and target.is_file():
            out.append(target)
        elif target.is_file():
            raise WrsimError(
                f"{target}: an input record file has no scenario to run in closed loop; give record folders"
            )
        else:
            raise WrsimError(f"{target}: no such record (a folder of `wrsim record`, or an input record file)")
    return out


def load_record(folder: Path) -> Record:
    """The record `record` wrote into `folder`."""
    try:
        with np.load(folder / TRACE) as z:
            return Record(folder.name, folder, int(z["start_position"]), z["time"], z["force"], z["glass"])
    except (OSError, KeyError, ValueError) as e:
        raise WrsimError(f"{folder}: not a record of wrsim's ({e})") from None


_LEVELS = "UX01ZWLH-"


def read_inputs(path: Path, out: Path) -> int:
    """Check the input record `path` (ecu_software's record_out, or a real door's in the same columns, separated by
    blanks or commas: t_us, hall_a, hall_b, supply_dv, command, and a PWM ECU's current_code (its ADC code, 0 ..
    1023) where the ECU measures the current; '#' starts a comment) and write it to `out` in the form tb_replay reads.
    Returns the number of input lines; an error names the file, line and column."""
    try:
        text = path.read_text(encoding="utf-8-sig")  # a byte-order mark (a spreadsheet's CSV) is no column
    except (OSError, UnicodeDecodeError) as e:
        raise WrsimError(f"{path}: cannot read the input record ({e})") from None
    lines, last = ["# ecu_software input record: t_us hall_a hall_b supply_dv command [current_code]"], -1
    for n, raw in enumerate(text.splitlines(), start=1):
        body = raw.split("#", 1)[0].replace(",", " ").split()
        if not body or (n == 1 and body[0].lower() == "t_us"):  # blank, comment, or a CSV header
            continue
        where = f"{path}:{n}"
        if len(body) not in (5, 6):
            raise WrsimError(
                f"{where}: expected 5 or 6 columns 't_us hall_a hall_b supply_dv command [current_code]', found "
                f"{len(body)}"
            )
        t, a, b, supply, command = body[:5]
        current = ""
        if len(body) == 6:
            if not body[5].isdigit() or int(body[5]) > 1023:
                raise WrsimError(f"{where}: column 6 (current_code): '{body[5]}' is not an ADC code (0 .. 1023)")
            current = f" {int(body[5])}"
        if not t.isdigit() or int(t) >= 2**31:
            raise WrsimError(f"{where}: column 1 (t_us): '{t}' is not a time in us (0 .. 2**31-1)")
        if int(t) < last:
            raise WrsimError(f"{where}: column 1 (t_us): {t} us goes back (the line before is at {last} us)")
        for col, (name, value, width) in enumerate((("hall_a", a, 1), ("hall_b", b, 1)), start=2):
            if len(value) != width or value.upper() not in _LEVELS:
                raise WrsimError(f"{where}: column {col} ({name}): '{value}' is not a std_logic level ({_LEVELS})")
        try:
            code = int(supply)
        except ValueError:
            code = -2
        if not -1 <= code <= 255:
            raise WrsimError(
                f"{where}: column 4 (supply_dv): '{supply}' is not a supply in 0.1 V (0 .. 255, -1 unknown)"
            )
        if len(command) != 2 or any(c not in _LEVELS for c in command.upper()):
            raise WrsimError(f"{where}: column 5 (command): '{command}' is not two std_logic levels (01 up, 10 down)")
        last = int(t)
        lines.append(f"{t} {a.upper()} {b.upper()} {code} {command.upper()}{current}")
    if len(lines) == 1:
        raise WrsimError(f"{path}: the input record has no lines")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return len(lines) - 1


def ecu_generics(lib: Library, pset: ParamSet | None) -> dict[str, int | bool | str]:
    """The ECU software's generics on the closed-loop testbench with the parameter set `pset` (an algorithm's set
    laid over the system set), at the set's `[ambient] temperature`: what the replay gives tb_replay."""
    from wrsim.data.temperature import at_temperature

    design = elaborate(lib, TESTBENCH, None if pset is None else at_temperature(pset), {})
    for d in design.top.digital:
        if d.label == "ecu":
            return dict(d.generics)
    raise WrsimError(f"{TESTBENCH} has no ECU instance 'ecu'")


class Replayer:
    """The ECU software on records (tb_replay, built once per `workdir`; `c_algorithm` replaces antipinch.c). `keep`:
    each replay's files stay in `workdir`/replays/<record>/<name>/ (the result, and the learned state where that
    replay learned it); else they are removed once read (a calibration replays thousands of times). A learned
    state is replayed once per normalization record and generics and kept in `workdir`/learned/."""

    def __init__(self, workdir: Path, lib: Library | None = None, c_algorithm: Path | None = None, keep: bool = False):
        lib = lib or load_library(paths.LIBRARY)
        replace = None if c_algorithm is None else {"antipinch.c": c_algorithm}
        self.workdir, self.keep = workdir, keep
        self.executable = executable(REPLAY_TOP, lib.digital_files([REPLAY_TOP]), workdir, replace)
        self._learning: dict[str, threading.Lock] = {}
        self._guard = threading.Lock()

    def run(self, inputs: Path, generics: Mapping[str, int | bool | str], folder: Path) -> Decision:
        """Replay the input record `inputs` (checked by `read_inputs`) with the ECU generics `generics`; files of the
        run in `folder`."""
        folder.mkdir(parents=True, exist_ok=True)
        result, checked = folder / "replay.txt", folder / INPUTS
        read_inputs(inputs, checked)
        args = {k: v for k, v in generics.items() if k not in ("record_out", "reverse_on_pinch")}
        args.update(record_file=str(checked.resolve()), result_file=str(result.resolve()))
        proc = run_child(
            [str(self.executable), *(f"-g{k}={_text(v)}" for k, v in args.items()), "--assert-level=error"],
            capture_output=True,
            text=True,
            cwd=folder,
            timeout=_TIMEOUT,
            stdin=subprocess.DEVNULL,
        )
        said = [ln for ln in (proc.stdout + proc.stderr).splitlines() if "tb_replay:" in ln or "ecu_software:" in ln]
        if proc.returncode != 0 or not result.is_file():
            why = said[0].split("):", 1)[-1].strip() if said else proc.stderr[-500:].strip()
            if not why:  # killed by a signal, or an exit without a word
                why = (
                    f"tb_replay was killed by signal {-proc.returncode}"
                    if proc.returncode < 0
                    else f"tb_replay exited with status {proc.returncode} and said nothing"
                )
            raise WrsimError(f"replay of {inputs} failed: {why}")
        words = result.read_text(encoding="utf-8").split()
        if words[:1] == ["pinch"]:
            return Decision(int(words[1]) * 1e-6, int(words[2]))
        return Decision(None, None)

    def replay(self, rec: Record, generics: Mapping[str, int | bool | str], name: str) -> Decision:
        """The decision of the algorithm with ECU generics `generics` on `rec`: a warm record's normalization run
        replayed first (the algorithm learns its own state there), then the case run. `name` names the folder."""
        folder = self.workdir / "replays" / rec.name / name
        if not self.keep:
            folder.parent.mkdir(parents=True, exist_ok=True)
            with tempfile.TemporaryDirectory(dir=folder.parent, prefix=f"{name}-") as tmp:
                return self._replay(rec, generics, Path(tmp))
        return self._replay(rec, generics, folder)

    def _replay(self, rec: Record, generics: Mapping[str, int | bool | str], folder: Path) -> Decision:
        values = {k: v for k, v in generics.items() if k not in ("learned_file", "learned_out", "start_position")}
        if rec.learning is not None:
            if generics.get("algorithm") == 1:
                raise WrsimError(
                    f"record {rec.name} starts warm (a learned state): the C algorithm keeps its memory in C and takes "
                    f"no warm start; replay it on a cold record"
                )
            learned = self._learned(rec, values, folder)
            values = {**values, "learned_file": str(learned), "start_position": rec.start_position}
        return self.run(rec.inputs, values, folder)

    def _learned(self, rec: Record, values: Mapping[str, int | bool | str], folder: Path) -> Path:
        """The learned state the algorithm takes from `rec`'s normalization run: replayed once per normalization
        record, ECU generics and build (the cases of a fleet's door share one), kept under workdir/learned/."""
        assert rec.learning is not None
        key = hashlib.sha256(
            repr((rec.learning.read_bytes(), sorted(values.items()), str(self.executable))).encode()
        ).hexdigest()[:24]
        kept = self.workdir / "learned" / f"{key}.txt"
        with self._guard:
            lock = self._learning.setdefault(key, threading.Lock())
        with lock:
            if not kept.is_file():
                learned = (folder / "learned.txt").resolve()
                first = self.run(rec.learning, {**values, "learned_out": str(learned)}, folder / "learn")
                if first.detected is not None:
                    raise WrsimError(
                        f"{rec.learning}: the normalization run of record {rec.name} reversed in the replay"
                    )
                kept.parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(learned, kept.with_suffix(".tmp"))
                kept.with_suffix(".tmp").replace(kept)
        return kept.resolve()


def _text(v: int | bool | str | float) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float) and v.is_integer():
        return str(int(v))
    return str(v)


REPLAY_COLUMNS = ["record", "algorithm", "detection [s]", "position [edges]", "recorded force there [N]"]


def replay_table(
    targets: Sequence[str | Path],
    algorithms: Sequence[str | Path],
    workdir: Path,
    user: Sequence[str | Path] = (),
    c_algorithm: Path | None = None,
) -> list[list[str]]:
    """Replay every algorithm (parameter sets laid over the system set and `user`) on every record of `targets`:
    record folders (`record`), folders holding them, or input record files of a real door (cold: from power-up).
    One row per record and algorithm (`REPLAY_COLUMNS`)."""
    from wrsim.benches.score import algorithm_file

    records = find_records(targets, files=True)
    lib = load_library(paths.LIBRARY)
    replayer = Replayer(workdir, lib, c_algorithm, keep=True)
    base = scenario_params(user)
    rows = []
    for alg in algorithms:
        file = algorithm_file(alg)
        generics = ecu_generics(lib, base.beneath(load_params(file)))
        for rec in records:
            if isinstance(rec, Record) and rec.learning is not None and generics.get("algorithm") == 1:
                rows.append([rec.name, file.stem, "C: cold records only", "-", "-"])
                continue
            if isinstance(rec, Record):
                d, name = replayer.replay(rec, generics, file.stem), rec.name
                force = "-" if d.detected is None else f"{rec.force_at(d.detected):.1f}"
            else:
                d, name, force = replayer.run(rec, generics, workdir / "replays" / rec.stem / file.stem), rec.name, "-"
            rows.append(
                [
                    name,
                    file.stem,
                    "none" if d.detected is None else f"{d.detected:.6f}",
                    "-" if d.position is None else str(d.position),
                    force,
                ]
            )
    return rows


@dataclass(frozen=True)
class Check:
    """One record replayed with one algorithm against the closed-loop run of its scenario with that algorithm."""

    record: str
    algorithm: str
    replayed: float | None  # [s] the replay's first detection
    closed: float | None  # [s] the Hall-A edge the closed loop first detected on
    peak: float  # [N] the closed loop's largest gauge force (a catalog case is one closing)
    force: float | None  # [N] the record's gauge force at the replayed detection
    error: str = ""  # why the closed-loop run could not be judged

    @property
    def same(self) -> bool:
        """Both detect on the same Hall edge (within the 1 us timer and d_cosim's 1 us), or neither detects."""
        if self.error:
            return False
        if self.replayed is None or self.closed is None:
            return self.replayed is None and self.closed is None
        return abs(self.replayed - self.closed) < 2.5e-6


def against_closed_loop(
    records: Sequence[Record],
    scenarios: Sequence[str | Path],
    algorithms: Sequence[str | Path],
    workdir: Path,
    user: Sequence[str | Path] = (),
    runner: Runner | None = None,
    ecu: str | None = None,
) -> list[Check]:
    """Replay every algorithm on every record and run the record's scenario (by name among `scenarios`) in closed
    loop with that algorithm's set laid on top of the scenario's: the first detection of each, and the closed loop's
    peak force. What shows that the replay decides as the closed loop does. `ecu`: the ECU concept the records were
    made with, if not the scenarios' own."""
    from wrsim.benches.run import simulator
    from wrsim.benches.score import algorithm_file

    by_name = {p.stem: p for p in map(Path, scenarios)}
    runner = runner or simulator()
    lib = load_library(paths.LIBRARY)
    base = scenario_params(user)
    replayer = Replayer(workdir / "replay", lib)
    warm = WarmStart(lib, runner, workdir / "learn")
    jobs = []
    for alg in map(algorithm_file, algorithms):
        for rec in records:
            if rec.name not in by_name:
                raise WrsimError(f"record {rec.name}: no scenario of that name among those given")
            s = load_scenario(by_name[rec.name])
            if ecu is not None:
                s = dataclasses.replace(s, ecu=ecu)
            generics = ecu_generics(lib, concept_over(base, s.ecu).beneath(load_params(alg)))
            if rec.learning is not None and generics.get("algorithm") == 1:
                continue  # the C algorithm takes no warm start, in closed loop as in the replay
            jobs.append(
                (rec, alg, replayer.replay(rec, generics, alg.stem), dataclasses.replace(s, params=(*s.params, alg)))
            )

    def closed(job: tuple[Record, Path, Decision, Scenario]) -> Check:
        rec, alg, decision, s = job
        bench = scenario_bench(s, base, warm)
        try:
            (sim,), _ = simulate_runs(bench, lib, base, runner, workdir / "closed" / alg.stem)
        except WrsimError as e:  # one case that cannot be run must not hide the others
            return Check(rec.name, alg.stem, decision.detected, None, float("nan"), None, str(e).splitlines()[0])
        # the first detection and the largest force of the run (a catalog case is one closing; a run up that
        # does not end, e.g. a glass creeping into a cold seal slower than the stall time, is still judged)
        w = sim.waves
        rises = np.flatnonzero(np.diff((w["pinch"] > 0.5).astype(int)) == 1) + 1
        force = None if decision.detected is None else rec.force_at(decision.detected)
        first = float(w.time[rises[0]]) if rises.size else None
        if first is not None:  # the Hall-A edge the ECU decided on: the last at or before its flag rose
            edges = w.time[1:][np.diff((w["hall_a"] > 0.5).astype(int)) != 0]
            edges = edges[edges <= first + 1e-6]
            if edges.size and first - edges[-1] < _DELIVERY_S:
                first = float(edges[-1])
        return Check(rec.name, alg.stem, decision.detected, first, float(np.max(w["pinch_force"])), force)

    with concurrent.futures.ThreadPoolExecutor(max_workers=_workers(len(jobs))) as pool:
        return list(pool.map(closed, jobs))


# [s] the longest a closed loop's ECU output may reach the analog side after the Hall edge it reacts to: with the PWM
# ECU (no relay switched by the detection) one analog step, at most the closed-loop benches' max_step (1 ms) --
# shorter than a Hall edge's period (some 3.5 ms at speed), so the edge before the flag is the one decided on
_DELIVERY_S = 1.0e-3


def _workers(jobs: int) -> int:
    """Threads that prepare and wait for simulator runs (benches.core limits the simulator processes to the cores)."""
    return max(1, min(jobs, 2 * (os.cpu_count() or 1)))
