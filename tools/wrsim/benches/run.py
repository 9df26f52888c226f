"""Running benches as a user does: each bench with its own parameter set, its work folder and its published result
(a bench that fails to run is recorded as failed and the others still run), and a user's own testbench
(`wrsim run`)."""

from __future__ import annotations

import concurrent.futures
import os
import sys
import time
import traceback
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
from tqdm import tqdm

from wrsim import paths
from wrsim.backend.ngspice.batch import NgspiceBatch
from wrsim.backend.ngspice.netlist import Analysis
from wrsim.backend.ngspice.raw import NotSaved
from wrsim.benches.convergence import tighter, with_convergence
from wrsim.benches.core import Bench, Judgement, Run, Simulated, bench_params, run_bench, testbench_params
from wrsim.benches.known import deviations
from wrsim.benches.scenario import ECUS, check_ecu
from wrsim.data.params import ParamSet
from wrsim.data.publish import unique_folder
from wrsim.elab.generics import GenericValue, top_generics
from wrsim.elab.library import Library, load_library
from wrsim.errors import WrsimError
from wrsim.report.results import bench_verdict, write_bench_result, write_failure, write_index
from wrsim.results import BenchResult, Grid, Plot, Signal
from wrsim.runner import Runner

__all__ = ["simulator", "run_benches", "run_files", "solver_waveforms"]


def simulator(c_algorithm: str | Path | None = None) -> NgspiceBatch:
    """The simulator of the benches; `c_algorithm`: a C file linked into the ECU instead of the shipped
    vhdl/digital/antipinch.c (the functions of that file; the ECU calls them with `[ecu_software] algorithm = 1`,
    params/antipinch/c_twin.txt)."""
    if c_algorithm is None:
        return NgspiceBatch()
    path = Path(c_algorithm)
    if path.suffix != ".c" or not path.is_file():
        raise WrsimError(
            f"{path}: {'not found' if not path.exists() else 'not a C file'} (an anti-pinch algorithm "
            f"in C implements the functions of vhdl/digital/antipinch.c)"
        )
    return NgspiceBatch(c_files={"antipinch.c": path})


def run_benches(
    benches: list[Bench],
    user: Sequence[str | Path] = (),
    results: Path = paths.RESULTS,
    lib: Library | None = None,
    c_algorithm: str | Path | None = None,
    sets: Mapping[str, ParamSet | None] | None = None,
    runner: Runner | None = None,
    convergence: float | None = None,
    work: Path | None = None,
) -> list[BenchResult | dict]:
    """Run `benches`, each in a work folder of its own (`work`/<bench>/<run id>/; by default beside_results(results,
    "work")), publish each result
    under `results/<bench>/` and rewrite the index. A bench that fails keeps its last good result and gets a
    failure record beside it; the others still run. Returns the results (a failed bench as {"bench", "passed":
    False, "error"}). User errors (unknown parameter set, bad library) are raised before anything runs.
    `c_algorithm`: see `simulator`. `sets`: each bench's parameter set by name, instead of `bench_params(bench,
    user)` (scenarios lay their own sets); `runner`: instead of `simulator(c_algorithm)`; `convergence`: a tighter
    reltol each bench also runs at, for its convergence note (benches.convergence)."""
    tight = {b.name: tighter(b, convergence) for b in benches} if convergence is not None else {}
    runner = runner or simulator(c_algorithm)
    runner.check()
    lib = lib or load_library(paths.LIBRARY)
    params = dict(sets) if sets is not None else {bench.name: bench_params(bench, user) for bench in benches}
    deviations()  # a malformed testbenches/known.toml stops before anything runs
    for bench in benches:  # the PWM ECU's profile of every run that has that ECU, before anything runs
        checked: set[str] = set()
        for r in bench.runs:
            own = repr(r.params)
            if r.generics.get("ecu_kind") == ECUS["pwm"][0] and own not in checked:
                checked.add(own)
                pset = r.parameters(params[bench.name])
                if pset is not None:
                    check_ecu(lib, pset, f"{bench.name} ({r.label})")
    # progress on a terminal: a bar over every run of every bench (elapsed, ETA) and a line per finished bench; off a
    # terminal (a CI log) the line per finished bench alone, as it finishes
    bar = tqdm(
        total=sum(len(b.runs) for b in benches) * (2 if tight else 1),
        unit="run",
        desc="benches",
        disable=None,
        bar_format="{desc}: {n_fmt}/{total_fmt} runs |{bar}| {elapsed} elapsed, ETA {remaining} {postfix}",
    )

    def finished(line: str) -> None:
        if bar.disable:
            print(line, flush=True)
        else:
            bar.write(line)

    def run(bench: Bench) -> BenchResult | dict:
        workdir = unique_folder((work or paths.beside_results(results, "work")) / bench.name)
        t0 = time.perf_counter()

        def done(r: Run) -> None:
            bar.set_postfix_str(f"{bench.name} ({r.label})", refresh=False)
            bar.update(1)

        try:
            result = run_bench(bench, lib, params[bench.name], runner, workdir, on_run=done)
            if bench.name in tight:
                again = run_bench(tight[bench.name], lib, params[bench.name], runner, workdir / "tighter", on_run=done)
                result = with_convergence(result, again, bench.reltol, tight[bench.name].reltol)
            write_bench_result(results, result)
            finished(f"{bench.name}: {bench_verdict(result)} in {time.perf_counter() - t0:.1f} s")
            return result
        except WrsimError as e:
            message = str(e)
        except Exception as e:  # noqa: BLE001 - a defect in one bench must not stop the others
            log = workdir / "traceback.txt"
            try:  # the work folder may be gone (removed under a running bench)
                log.parent.mkdir(parents=True, exist_ok=True)
                log.write_text("".join(traceback.format_exception(e)), encoding="utf-8")
                where = f"traceback: {log}"
            except OSError as why:
                where = f"no traceback written: {why}"
            message = f"internal error: {type(e).__name__}: {e} ({where})"
        write_failure(results, bench.name, message)
        finished(f"{bench.name}: error after {time.perf_counter() - t0:.1f} s")
        return {"bench": bench.name, "passed": False, "error": message, "metrics": {}}

    # Benches run side by side (their simulator processes share the cores, benches.core), so that a bench of one
    # run does not leave a core idle; results keep the order of `benches`.
    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=min(len(benches), os.cpu_count() or 1)) as pool:
            out = list(pool.map(run, benches))
    finally:
        bar.close()
    write_index(results)
    return out


_PLOTTED = 6  # signals in a user run's plot (the waveform table has all)


def run_files(
    files: Sequence[str | Path],
    top: str,
    stop: float,
    max_step: float | None = None,
    libraries: dict[str, list[str | Path]] | None = None,
    params: Sequence[str | Path] = (),
    generics: Mapping[str, GenericValue] | None = None,
    results: Path = paths.RESULTS,
    with_models: bool = False,
    reltol: float | None = None,
    save: Sequence[str] = (),
    resample: int | None = None,
    timeout: float = 600.0,
    quiescent: bool = False,
    sweep: tuple[str, Sequence[float]] | None = None,
    ac: tuple[float, float, int] | None = None,
    noise: tuple[str, float, float, int, str | None] | None = None,
) -> BenchResult:
    """Simulate a user's testbench `top` from `files` (files or folders, with the IEEE 1076.1.1 packages of
    vhdl/ieee and `libraries`: name -> files or folders; `with_models`: also wrsim's model library) and publish
    the waveforms (CSV and MDF4 at the solver's own time points, or `resample` uniform points; a plot of the first
    few) as results/run/<top>/. The parameter set is `bench_params`'s: the one the testbench's header names (`parameter
    set: ...`), then each of `params` in order, at the set's ambient temperature. `generics`: top-level generic
    values as users write them (elab.generics). `reltol` (default: the transient analysis's), `save`: the
    quantities and signals to write (all when empty). `timeout`: the simulator's wall time [s] before the run
    is stopped with an error (a model whose events never end). `quiescent`: the quiescent point instead of a
    transient (every quantity's value at t = 0, where the transient starts); `sweep` (a top-level generic and its
    values, in the unit of its subtype): a quiescent point per value, the waveforms over the generic (a DC sweep);
    `ac` (FSTART, FSTOP [Hz], points a decade): the small-signal response around the quiescent point to the spectrum
    source quantities, magnitude [dB] and phase [deg] of every quantity (ac.csv, a Bode plot ac.png); `noise`
    (a quantity, then as `ac`, then a spectrum source quantity or None): the density its noise source quantities
    give that quantity, and referred to the spectrum source's value when one is given (noise.csv, noise.png).
    A file that does not parse stops the run only when `top`
    needs a unit it would give. With the models, a unit of `files` replaces the library's unit of the same name
    (e.g. the packages of `wrsim export`)."""
    if with_models:
        lib = load_library([paths.VHDL], libraries, tolerant=True, over=files)
    else:
        lib = load_library([paths.VHDL / "ieee", *files], libraries, tolerant=True)
    values = top_generics(lib, top.lower(), generics or {})
    runs: tuple[Run, ...] = (Run(top.lower(), dict(values)),)
    if sweep is not None:
        generic, points = sweep
        runs = tuple(
            Run(f"{generic}={v:g}", dict(top_generics(lib, top.lower(), {**(generics or {}), generic: v}, "--dc")))
            for v in points
        )
    if quiescent or sweep is not None or ac is not None or noise is not None:
        stop = _AT_REST
    base = testbench_params(lib, top.lower())
    pset = bench_params(base, params)
    runner = simulator()
    runner.check()

    notes: list[str] = []  # what the lowering accepted and left out (frequency-domain sources)

    def judge(bench: Bench, sims: list[Simulated], table: object, session: object) -> Judgement:
        notes.extend(n for s in sims for m in [*s.design.models, s.design.top] for n in m.notes)
        if ac is not None:
            return Judgement(metrics=[], plots=_bode(top, sims[0]), waveforms=[])
        if noise is not None:
            return Judgement(metrics=[], plots=_noise_density(top, noise[0], noise[4], sims[0]), waveforms=[])
        if quiescent or sweep is not None:
            declared = {g.name: g.unit for g in lib.entity(top.lower()).generics}
            points = at_rest(sims, sweep, (declared.get(sweep[0].lower()) or "1") if sweep else "")
            columns = points if sweep else points[1:]  # the swept generic, then the quantities
            table = Grid(
                f"{top}: the quiescent point" + (f" over {sweep[0]}" if sweep else ""),
                [s.label for s in columns],
                [[f"{s.values[k]:.9g}" for s in columns] for k in range(len(points[0].values))],
                "dc.csv" if sweep else "op.csv",
            )
            return Judgement(
                metrics=[], plots=[table, *_sweep_plots(top, points)], waveforms=points if sweep is None else []
            )
        waves = solver_waveforms(sims[0], resample, bench.save)
        plot = Plot(
            f"{top}: {', '.join(w.name for w in waves[1 : _PLOTTED + 1])}",
            waves[0],
            waves[1 : _PLOTTED + 1],
            [],
            [],
            "waveforms.png",
        )
        return Judgement(metrics=[], plots=[plot] if len(waves) > 1 else [], waveforms=waves)

    bench = Bench(
        name=top.lower(),
        entity=top.lower(),
        description=f"{top} from {', '.join(map(str, files))}",
        stop=stop,
        max_step=max_step,
        runs=runs,
        judge=judge,
        params=str(base or ""),
        save=tuple(save),
        reltol=reltol or Analysis(stop).reltol,
        timeout=timeout,
        ac=ac,
        noise=noise,
    )
    result = run_bench(bench, lib, pset, runner, unique_folder(paths.WORK / "run" / bench.name))
    write_bench_result(results / "run", result)
    write_index(results / "run")
    for note in dict.fromkeys(notes):
        print(f"note: {note}", file=sys.stderr)
    return result


_AT_REST = 1e-9  # [s] the transient a quiescent point runs: its first point, at t = 0, is the quiescent point


def at_rest(sims: list[Simulated], sweep: tuple[str, Sequence[float]] | None, unit: str = "") -> list[Signal]:
    """The quiescent point of each run (the first point of its transient): `[0]` is the swept generic in `unit` (or
    time 0 for one point), then every quantity and signal by hierarchical name."""
    x = Signal("time", "s", np.zeros(1)) if sweep is None else Signal(sweep[0], unit, np.asarray(sweep[1], float))
    rows = [{s.name: s for s in solver_waveforms(sim)[1:]} for sim in sims]
    return [
        x,
        *(Signal(s.name, s.unit, np.array([float(r[s.name].values[0]) for r in rows])) for s in rows[0].values()),
    ]


def _bode(top: str, sim: Simulated) -> list[Plot | Grid]:
    """The frequency response of every quantity: a table (magnitude in dB, phase in degrees, over frequency) and a
    Bode plot of the first few."""
    f = Signal("frequency", "Hz", sim.waves.time)
    magnitude: list[Signal] = []
    phase: list[Signal] = []
    for name in sorted(sim.waves.probes):
        if sim.waves.probes[name].bits:
            continue  # a digital signal has no small-signal response
        x = np.asarray(sim.waves[name], dtype=complex)
        with np.errstate(divide="ignore"):
            magnitude.append(Signal(f"|{name}|", "dB", 20.0 * np.log10(np.abs(x))))
        phase.append(Signal(f"{name} phase", "deg", np.degrees(np.angle(x))))
    table = Grid(
        f"{top}: the small-signal response",
        [f.label, *(s.label for pair in zip(magnitude, phase) for s in pair)],
        [
            [f"{f.values[k]:.9g}", *(f"{s.values[k]:.9g}" for pair in zip(magnitude, phase) for s in pair)]
            for k in range(len(f.values))
        ],
        "ac.csv",
    )
    shown = slice(0, _PLOTTED // 2)
    return [table, Plot(f"{top}: Bode", f, magnitude[shown], phase[shown], [], "ac.png", logx=True)]


def _noise_density(top: str, output: str, referred: str | None, sim: Simulated) -> list[Plot | Grid]:
    """The output noise density at `output` over frequency (ngspice's onoise_spectrum) and, with `referred` (a
    spectrum source quantity), the density at that source that would give it (inoise_spectrum: the output's
    divided by the gain from the source): a table and a plot."""
    f = Signal("frequency", "Hz", sim.waves.time)
    unit = sim.waves.probes[output].unit
    densities = [Signal(f"{output} noise", f"{unit}/sqrt(Hz)", np.asarray(sim.waves.vectors["onoise_spectrum"]).real)]
    if referred is not None:
        densities.append(
            Signal(
                f"{output} noise referred to {referred}",
                f"{sim.waves.probes[referred].unit}/sqrt(Hz)",
                np.asarray(sim.waves.vectors["inoise_spectrum"]).real,
            )
        )
    table = Grid(
        f"{top}: the noise density of {output}",
        [f.label, *(d.label for d in densities)],
        [[f"{v:.9g}" for v in row] for row in zip(f.values, *(d.values for d in densities))],
        "noise.csv",
    )
    return [table, Plot(f"{top}: noise of {output}", f, densities, [], [], "noise.png", logx=True)]


def _sweep_plots(top: str, waves: list[Signal]) -> list[Plot]:
    if len(waves[0].values) < 2 or len(waves) < 2:
        return []
    shown = waves[1 : _PLOTTED + 1]
    return [Plot(f"{top}: {', '.join(w.name for w in shown)} over {waves[0].name}", waves[0], shown, [], [], "dc.png")]


def solver_waveforms(sim: Simulated, resample: int | None = None, save: Sequence[str] = ()) -> list[Signal]:
    """The quantities and signals `save` names (every one saved when empty) of one run by hierarchical name with its
    unit, at the solver's time points (or `resample` uniform points over the run); `[0]` is time[s]."""
    t = sim.waves.time
    grid = t if resample is None else np.linspace(float(t[0]), float(t[-1]), resample)
    out = [Signal("time", "s", grid)]
    for name in sorted(save or sim.waves.probes):
        try:
            values = sim.waves[name]
        except NotSaved:
            continue
        out.append(
            Signal(name, sim.waves.probes[name].unit, values if resample is None else np.interp(grid, t, values))
        )
    return out
