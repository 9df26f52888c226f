"""`wrsim`: the command line. Argument parsing and printing only; the work is done by the public API. Every user
error is one line on stderr and exit status 2; a bench that misses its tolerance (not a documented deviation, KNOWN)
or leaves its waveform tubes makes `wrsim testbench` exit 1."""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import sys
import tempfile
from pathlib import Path
from typing import Any, NoReturn

from wrsim import paths
from wrsim.errors import WrsimError

__all__ = ["main", "build_parser"]


def cmd_testbench(args: argparse.Namespace) -> int:
    from wrsim.benches import select_benches
    from wrsim.benches.known import sets_label
    from wrsim.benches.run import run_benches
    from wrsim.report.results import format_table

    # a C algorithm runs as algorithm 1 (params/antipinch/c_twin.txt) unless the user's set says otherwise
    params = args.params or ([paths.ALGORITHMS / "c_twin.txt"] if args.c_algorithm else [])
    results = run_benches(
        select_benches(args.bench),
        params,
        Path(args.results),
        c_algorithm=args.c_algorithm,
        convergence=args.convergence,
    )
    print(format_table(results))
    # the references are the default parameter set's: another set is no regression
    regressions = [] if params else _compare(results, Path(args.results))
    for reg in regressions:
        print(reg.summary())
    print(f"results: {Path(args.results) / 'index.html'}")
    return _summary(results, regressions, sets_label(params))


def cmd_regression(args: argparse.Namespace) -> int:
    from wrsim.benches import BENCHES, select_benches
    from wrsim.benches.run import run_benches
    from wrsim.report.regression import bless, reference_file

    if args.bless and not (args.reason or "").strip():
        raise WrsimError("--bless needs a --reason: one line that says why the references change")
    benches = select_benches(args.bench)
    results = run_benches(benches, args.params, Path(args.results))
    failed = [r for r in results if isinstance(r, dict)]
    for f in failed:
        print(f"{f['bench']}: error: {f['error']}")
    if args.bless:
        if failed:
            raise WrsimError(f"{len(failed)} bench(es) failed to run; no reference was blessed")
        for r in results:
            if not isinstance(r, dict):
                path = bless(r.bench, r.waveforms, BENCHES[r.bench].stop, args.reason, " ".join(args.params))
                print(f"{r.bench}: reference blessed: {path}")
        return 0
    regressions = _compare(results, Path(args.results))
    for reg in regressions:
        print(reg.summary())
    missing = [r.bench for r in results if not isinstance(r, dict) and not reference_file(r.bench).exists()]
    for bench in missing:
        print(f"{bench}: no reference (wrsim regression --bench {bench} --bless --reason '...')")
    bad = sum(not reg.passed for reg in regressions) + len(missing) + len(failed)
    print(
        f"regression: {len(regressions) - sum(not r.passed for r in regressions)} of {len(results)} benches "
        f"within their tubes" + (f"; {bad} failing" if bad else "") + f"; pages: {Path(args.results) / 'regression'}"
    )
    return 1 if bad else 0


def cmd_report_check(args: argparse.Namespace) -> int:
    from wrsim.report.browser import check_pages

    root = Path(args.results)
    pages = [root / "index.html", *sorted(root.glob("*/index.html")), *sorted(root.glob("regression/*/*.html"))]
    problems = check_pages(pages, root / "screenshots")
    for problem in problems:
        print(problem)
    print(f"report-check: {len(pages)} pages, {len(problems)} problems; screenshots: {root / 'screenshots'}")
    return 1 if problems else 0


def _compare(results: list, root: Path) -> list:
    """The waveform regression of every bench that ran and has a reference (pages under root/regression/)."""
    from wrsim.report.regression import compare

    out = []
    for r in results:
        if not isinstance(r, dict):
            reg = compare(r.bench, r.waveforms, root / "regression")
            if reg is not None:
                out.append(reg)
    return out


def _summary(results: list, regressions: list, sets: str) -> int:
    """Print the verdicts' count (the KNOWN rows listed) and return the exit status: 0 when nothing but known
    deviations remain, 1 on a FAIL, an error or a regression. `sets`: the user's sets (known.sets_label), whose
    deviations that pass now are named."""
    from wrsim.benches.known import deviations
    from wrsim.report.results import result_dict

    rows = [r if isinstance(r, dict) else result_dict(r) for r in results]
    errors = [d["bench"] for d in rows if d.get("error")]
    failing = [
        f"{d['bench']}: {name}"
        for d in rows
        if not d.get("error")
        for name, m in d["metrics"].items()
        if not m["pass"] and not m.get("known")
    ]
    known = [
        f"{d['bench']}: {name}: {m['known']}"
        for d in rows
        for name, m in d["metrics"].items()
        if not m["pass"] and m.get("known")
    ]
    regressed = [reg.bench for reg in regressions if not reg.passed]
    passed = sum(1 for d in rows for m in d["metrics"].values() if m["pass"])
    print(
        f"summary: {passed} PASS, {len(known)} KNOWN, {len(failing)} FAIL, {len(errors)} errors, "
        f"{len(regressed)} regressions"
    )
    for line in known:
        print(f"  KNOWN {line}")
    for line in failing:
        print(f"  FAIL {line}")
    for bench in errors:
        print(f"  ERROR {bench}")
    for bench in regressed:
        print(f"  REGRESSION {bench}")
    ran = {d["bench"]: d["metrics"] for d in rows if not d.get("error")}
    for bench, name in deviations(sets=sets):
        if name in ran.get(bench, {}) and ran[bench][name]["pass"]:
            print(f"  {bench}: {name} passes now: remove its entry from {paths.KNOWN}")
    return 1 if failing or errors or regressed else 0


def cmd_score(args: argparse.Namespace) -> int:
    from wrsim.benches.score import algorithm_sets, score_algorithms
    from wrsim.results import Grid

    if args.fleet:
        return _score_fleet(args)
    algorithms = args.algorithm or (["c_twin"] if args.c_algorithm else algorithm_sets())
    _, page = score_algorithms(algorithms, args.params, Path(args.results), c_algorithm=args.c_algorithm)
    grid = page.plots[0]
    assert isinstance(grid, Grid)
    _print_table([grid.columns, *grid.rows])
    print(f"results: {Path(args.results) / 'score' / 'score.html'}")
    return 0 if page.passed else 1


def _print_table(rows: list[list[str]]) -> None:
    """Rows of text cells as aligned columns, the first row the header."""
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    for row in rows:
        print("  ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip())


def _score_fleet(args: argparse.Namespace) -> int:
    from wrsim.benches.score import algorithm_sets
    from wrsim.results import Grid
    from wrsim.study.fleet import SUMMARY_COLUMNS, score_fleet

    if args.c_algorithm or args.params:
        raise WrsimError("--fleet scores the algorithms on the doors it draws: leave out --c-algorithm and --params")
    algorithms = args.algorithm or [p for p in algorithm_sets() if p.stem != "c_twin"]
    with contextlib.ExitStack() as stack:
        client = _dask_client(args, stack)
        _, page = score_fleet(args.fleet, args.samples, args.seed, args.catalog, algorithms, Path(args.results), client)
    grid = page.plots[0]
    assert isinstance(grid, Grid) and grid.columns == SUMMARY_COLUMNS
    _print_table([grid.columns, *grid.rows])
    print(f"results: {Path(args.results) / 'fleet' / 'index.html'}")
    return 0 if page.passed else 1


def _limit(text: str) -> tuple[str, float | None, float | None]:
    name, eq, span = text.rpartition("=")
    lo, dots, hi = span.partition("..")
    if not eq or not name.strip() or not dots:
        raise argparse.ArgumentTypeError(
            f"'{text}': write OUTPUT=LOW..HIGH (either may be left out: 'peak force at 16 V=..100')"
        )
    return name.strip(), _finite(lo) if lo.strip() else None, _finite(hi) if hi.strip() else None


def _generic(text: str) -> tuple[str, str]:
    key, eq, value = text.partition("=")
    if not eq or not key.strip():
        raise argparse.ArgumentTypeError(
            f"'{text}': write GENERIC=VALUE (u_nominal=9V, pinch_position=320mm, "
            f"sequence_file=my/seq.txt, a boolean as true or false)"
        )
    return key.strip().lower(), value.strip()


def _generics(entity: str, given: list[tuple[str, str]] | None, lib=None) -> dict:
    """The `--set` values for the top-level generics of `entity`, typed and in the generics' units."""
    from wrsim.elab import load_library
    from wrsim.elab.generics import top_generics

    return top_generics(lib or load_library(paths.LIBRARY), entity.lower(), dict(given or []))


def cmd_study(args: argparse.Namespace) -> int:
    from wrsim.benches import select_benches
    from wrsim.study import StudySpec, rerun_sample, run_study
    from wrsim.study.report import statistics, write_study_page

    generics = _generics(select_benches([args.bench])[0].entity, args.set) if args.set else {}
    spec = StudySpec(
        args.bench,
        tuple(args.params),
        args.method,
        args.samples,
        args.seed,
        tuple(generics.items()),
        tuple(args.run or ()),
        args.stop,
        tuple(args.limit or ()),
        args.name or "",
    )
    results = Path(args.results)
    if args.rerun is not None:
        folder = rerun_sample(spec, args.rerun, results)
        print(f"sample {args.rerun}: {folder} ({folder.parent / 'index.html'})")
        return 0
    with contextlib.ExitStack() as stack:
        client = _dask_client(args, stack)
        study = run_study(spec, results, client=client, workers=args.workers, fresh=args.fresh)
    page = write_study_page(study)
    print(
        f"{'output':44s} {'unit':>5s} {'n':>5s} {'mean':>10s} {'std':>10s} {'p1':>10s} {'p99':>10s} "
        f"{'limits':>17s} {'Cpk / P(1)':>12s}"
    )
    for s in statistics(study):
        limits = f"{'' if s.lower is None else f'{s.lower:g}'}..{'' if s.upper is None else f'{s.upper:g}'}"
        quality = f"P={s.probability[0]:.3f}" if s.probability else "-" if s.cpk is None else f"{s.cpk:.2f}"
        print(
            f"{s.name[:44]:44s} {s.unit:>5s} {s.n:5d} {s.mean:10.4g} {s.std:10.4g} {s.percentiles[1]:10.4g} "
            f"{s.percentiles[99]:10.4g} {limits:>17s} {quality:>12s}"
        )
    failed = study.failed()
    for r in failed[:5]:
        print(f"sample {r['sample']} failed: {r['error'][:200]}")
    print(f"{len(study.rows) - len(failed)} samples, {len(failed)} failed; results: {study.file}; page: {page}")
    return 1 if failed else 0


def _library_map(text: str) -> tuple[str, str]:
    name, eq, folder = text.partition("=")
    if not eq or not name.strip() or not folder.strip():
        raise argparse.ArgumentTypeError(f"'{text}': write NAME=DIR (e.g. ieee_proposed=./ieee)")
    return name.strip().lower(), folder.strip()


def _dask_client(args: argparse.Namespace, stack: contextlib.ExitStack) -> Any:
    """The Dask client of `--scheduler ADDRESS` or `--dask-local N` (closed with `stack`), None without them."""
    if not (args.scheduler or args.dask_local):
        return None
    from distributed import Client

    from wrsim.study.engine import local_cluster

    target = args.scheduler or stack.enter_context(local_cluster(args.dask_local))
    try:
        return stack.enter_context(Client(target, timeout=30))
    except (OSError, ValueError) as e:  # unreachable, or not an address (ValueError)
        raise WrsimError(f"--scheduler {args.scheduler}: cannot reach the Dask scheduler ({e})") from None


def cmd_run(args: argparse.Namespace) -> int:
    from wrsim.benches.run import run_files

    libraries: dict[str, list[str | Path]] = {}
    for name, folder in args.lib or []:
        libraries.setdefault(name, []).append(folder)
    result = run_files(
        args.files,
        args.top,
        args.stop,
        args.max_step,
        libraries,
        args.params,
        dict(args.set or []),
        Path(args.results),
        args.with_models,
        args.reltol,
        args.save or (),
        args.resample,
    )
    print(
        f"{args.top}: {len(result.waveforms) - 1} waveforms over {args.stop:g} s "
        f"({len(result.waveforms[0].values)} points); results: {Path(args.results) / 'run' / result.bench}"
    )
    return 0


def cmd_scenario(args: argparse.Namespace) -> int:
    from wrsim.benches.scenario_run import SUMMARY_COLUMNS, run_scenarios, summary_rows

    scenarios, results = run_scenarios(args.targets, args.params, Path(args.results))
    rows = [SUMMARY_COLUMNS[:3], *(row[:3] for row in summary_rows(scenarios, results))]
    widths = [max(len(r[i]) for r in rows) for i in range(2)]
    for row in rows:
        print(f"{row[0]:{widths[0]}s}  {row[1]:{widths[1]}s}  {row[2]}")
    failed = sum(1 for r in results if isinstance(r, dict) or not r.passed)
    print(
        f"{len(results) - failed} of {len(results)} scenarios pass; pages: "
        f"{Path(args.results) / 'scenario' / 'index.html'}"
    )
    return 1 if failed else 0


def cmd_record(args: argparse.Namespace) -> int:
    from wrsim.benches.replay import record
    from wrsim.benches.scenario import find_scenarios, load_scenario

    scenarios = [load_scenario(f) for f in find_scenarios(args.targets)]  # every file checked before any run
    out = Path(args.out)
    for rec in record(scenarios, out, args.params):
        print(f"{rec.folder}: {rec.time[-1]:.2f} s, largest gauge force {float(rec.force.max()):.1f} N")
    return 0


def cmd_replay(args: argparse.Namespace) -> int:
    from wrsim.benches.replay import REPLAY_COLUMNS, replay_table
    from wrsim.benches.score import algorithm_sets

    algorithms = args.algorithm or (["c_twin"] if args.c_algorithm else algorithm_sets())
    c_file = Path(args.c_algorithm) if args.c_algorithm else None
    if args.closed_loop:
        return _replay_check(args, algorithms)
    rows = [REPLAY_COLUMNS, *replay_table(args.records, algorithms, paths.WORK / "replay", args.params, c_file)]
    _print_table(rows)
    return 0


def _replay_check(args: argparse.Namespace, algorithms: list) -> int:
    from wrsim.benches.replay import Record, against_closed_loop, find_records
    from wrsim.benches.scenario import find_scenarios

    if args.c_algorithm:
        raise WrsimError("--closed-loop checks the shipped algorithms; leave out --c-algorithm")
    records = [r for r in find_records(args.records) if isinstance(r, Record)]
    checks = against_closed_loop(
        records, find_scenarios(args.closed_loop), algorithms, paths.WORK / "replay-check", args.params
    )

    def at(t: float | None) -> str:
        return "none" if t is None else f"{t:.6f}"

    rows = [["record", "algorithm", "replayed [s]", "closed loop [s]", "same edge", "force there [N]", "peak [N]"]]
    for c in checks:
        force = "-" if c.force is None else f"{c.force:.1f}"
        rows.append(
            [
                c.record,
                c.algorithm,
                at(c.replayed),
                at(c.closed),
                "yes" if c.same else f"NO ({c.error})" if c.error else "NO",
                force,
                f"{c.peak:.1f}",
            ]
        )
    _print_table(rows)
    same = sum(c.same for c in checks)
    print(f"{same} of {len(checks)} replays decide on the closed loop's Hall edge")
    return 0 if same == len(checks) else 1


def cmd_calibrate(args: argparse.Namespace) -> int:
    from wrsim.study.calibrate import calibrate

    if args.samples < 1 or args.trials < 1:
        raise WrsimError("--samples and --trials must be at least 1")
    best, tuned, checked, target = calibrate(
        args.algorithm,
        args.fleet,
        args.samples,
        args.seed,
        args.trials,
        out=Path(args.out) if args.out else None,
    )
    print(", ".join(f"{k} = {v}" for k, v in best.items()))
    print(
        f"objective (worst p99 law-cell peak + 1000 N per failing door and case): tuning {tuned:.1f} N, "
        f"validation {checked:.1f} N"
    )
    print(f"calibrated set: {target}")
    return 0


def cmd_export(args: argparse.Namespace) -> int:
    from wrsim.benches.export import export_set

    out = (
        Path(args.out)
        if args.out
        else paths.EXPORT / (args.bench or "+".join(Path(p).stem for p in args.params) or "export")
    )
    for f in export_set(args.params, args.bench, out):
        print(f"{f.path}: package {f.package}, {len(f.changed)} value(s) of the set")
    print(
        "analyse these files into library WORK instead of the library's files of the same name (README, "
        '"Import into Saber or SystemVision")'
    )
    return 0


def cmd_bench(args: argparse.Namespace) -> int:
    if args.study:
        from wrsim.study.timing import time_studies

        print(
            f"{'study':16s} {'executor':>8s} {'workers':>7s} {'samples':>7s} {'failed':>6s} {'wall [s]':>9s} "
            f"{'samples/s':>9s}"
        )
        for st in time_studies(Path(args.results)):
            print(
                f"{st.study:16s} {st.executor:>8s} {st.workers:7d} {st.samples:7d} {st.failed:6d} {st.wall:9.1f} "
                f"{st.per_second:9.3f}",
                flush=True,
            )
        return 0
    if args.warm:
        from wrsim.benches.scenario_run import warm_checks
        from wrsim.data.publish import unique_folder

        print(
            f"{'warm twin':26s} {'closing':>7s} {'cold [N]':>9s} {'warm [N]':>9s} {'diff [N]':>8s} "
            f"{'cold det [ms]':>13s} {'warm det [ms]':>13s}"
        )
        for c in warm_checks(unique_folder(Path(args.results).parent / "work" / "warm-checks")):
            for k, (cp, wp, cl, wl) in enumerate(zip(c.cold_peaks, c.warm_peaks, c.cold_latency, c.warm_latency), 1):
                det = [f"{x * 1e3:13.1f}" if x is not None else f"{'-':>13s}" for x in (cl, wl)]
                print(f"{c.name:26s} {k:7d} {cp:9.2f} {wp:9.2f} {wp - cp:+8.2f} {det[0]} {det[1]}")
            print(
                f"{c.name:26s} wall: cold {c.cold_wall:.1f} s for {c.cold_simulated:g} s simulated, warm "
                f"{c.warm_wall:.1f} s for {c.warm_simulated:g} s ({1 - c.warm_wall / c.cold_wall:.0%} saved)"
            )
        return 0
    from wrsim.benches import select_benches
    from wrsim.benches.timing import time_benches

    benches = select_benches(args.bench)
    print(
        f"{'bench':22s} {'runs':>4s} {'sim [s]':>8s} {'wall [s]':>9s} {'wall/sim':>8s} {'ngspice':>8s} "
        f"{'GHDL':>6s} {'Python':>7s} {'points':>9s} {'rejected':>8s} {'iter/pt':>7s} {'landed':>7s} {'late':>5s} "
        f"{'ref [s]':>7s} {'x ref':>7s}"
    )
    notes = []
    for t in time_benches(benches, args.params, Path(args.results).parent / "work"):
        simulated = t.simulated * t.runs
        reference = (
            f"{t.reference:7.3f} {t.analysis / max(t.reference, 1e-9):7.1f}"
            if t.reference is not None
            else f"{'-':>7s} {'-':>7s}"
        )
        print(
            f"{t.bench:22s} {t.runs:4d} {simulated:8.2f} {t.wall:9.2f} {t.wall / simulated:8.3f} "
            f"{t.analysis:8.2f} {t.ghdl:6.2f} {t.python:7.2f} {t.points:9d} {t.rejected:8d} "
            f"{t.iterations / max(t.points, 1):7.2f} {t.landed:7d} {t.late:5d} {reference}"
        )
        notes += [f"no reference: {t.reference_note}"] if t.reference_note else []
    print(
        "wall/sim: wall seconds per simulated second; ngspice: its analysis time (CPU, summed over runs that may "
        "run at once); GHDL: inside the digital units' steps; Python: lowering, reading, judging; landed: steps "
        "shortened onto an 'above crossing; late: crossings the driver saw more than 1 us late (0 expected); "
        "ref: the reference solver, the same equations integrated by SUNDIALS "
        "IDAS [s]; x ref: ngspice's analysis time over it (docs/performance.md)"
    )
    for note in notes:
        print(note)
    return 0


def _design(entity: str, params: list[str], given: list[tuple[str, str]] | None):
    """The elaborated testbench `entity` of the library as `wrsim run` elaborates it: the parameter set its header
    names with the user's sets over it (benches.core.run_params), the `--set` values typed."""
    from wrsim.benches.core import run_params, testbench_params
    from wrsim.elab import elaborate, load_library

    lib = load_library(paths.LIBRARY)
    entity = entity.lower()
    generics = _generics(entity, given, lib)
    return elaborate(lib, entity, run_params(testbench_params(lib, entity), params), generics)


def cmd_lower(args: argparse.Namespace) -> int:
    from wrsim.backend.ngspice.netlist import Analysis, lower

    analysis = Analysis(
        args.stop, args.max_step, **({"reltol": args.reltol} if args.reltol else {}), save=tuple(args.save or ())
    )
    netlist = lower(_design(args.entity, args.params, args.set), analysis, args.entity.lower())
    if args.output:
        netlist.write(Path(args.output))
    else:
        sys.stdout.write(netlist.text)
    return 0


def cmd_dump(args: argparse.Namespace) -> int:
    from wrsim.frontend import parse_file, read_source, tokenize

    if args.stage == "tokens":
        for t in tokenize(read_source(args.target), args.target).tokens:
            print(f"{t.loc}\t{t.kind}\t{t.raw or t.text}")
    elif args.stage == "ast":
        for unit in parse_file(args.target).units:
            print(unit)
    else:
        from wrsim.elab.eliminate import eliminated

        print(eliminated(_design(args.target, args.params, [])).describe())
    return 0


def cmd_check(args: argparse.Namespace) -> int:
    from wrsim.benches import BENCHES
    from wrsim.benches.core import bench_params
    from wrsim.elab import elaborate, load_library, missing_units

    lib = load_library(paths.LIBRARY)
    problems = missing_units(lib)
    with tempfile.TemporaryDirectory() as tmp:
        for bench in BENCHES.values():
            for run in bench.runs:
                elaborate(
                    lib,
                    bench.entity,
                    run.parameters(bench_params(bench, args.params)),
                    run.resolved(Path(tmp) / run.label),
                )
    for p in problems:
        print(p)
    print(
        f"{len(lib.files)} files, {len(lib.entities)} entities, {len(BENCHES)} benches elaborated; "
        f"{len(problems)} unit problem(s)"
    )
    return 1 if problems else 0


def cmd_identify(args: argparse.Namespace) -> int:
    if args.what != "default":
        from wrsim.identify.command import identify_files

        opt = {k: Path(getattr(args, k)) if getattr(args, k) else None for k in ("out", "base", "report")}
        for line in identify_files(
            args.what,
            [Path(f) for f in args.files],
            ratio=args.ratio,
            method=args.method,
            celsius=args.celsius,
            voltage=args.voltage,
            **opt,
        ):
            print(line)
        return 0
    if args.files:
        raise WrsimError("identify default takes no files (it reads params/measurements/)")
    from wrsim.identify import write_default_set

    out = Path(args.out) if args.out else paths.PARAMS / f"{paths.DEFAULT_PARAMS}.txt"
    r = write_default_set(paths.ROOT, out)
    v = r["validation"]
    p = r["motor"]
    print(
        f"motor: ke={p.ke:.6g} V*s/rad kt={p.kt:.6g} N*m/A ra={p.ra:.6g} Ohm visc={p.visc:.6g} N*m*s/rad "
        f"mc={p.mc:.3g} N*m"
    )
    print(f"drive: ratio={r['worm_gear']['ratio']:g} eta={r['worm_gear']['eta']:g} m_gc={r['drive']['m_gc']:.6g} N*m")
    print(
        f"closed-form errors vs thesis lines: motor speed {v['motor_speed_pct']:.3f} %, current "
        f"{v['motor_current_pct']:.3f} %; drive speed {v['drive_speed_pct']:.3f} %, current "
        f"{v['drive_current_pct']:.3f} %"
    )
    print(f"wrote {out}")
    return 0


def cmd_averaging(args: argparse.Namespace) -> int:
    from wrsim.benches.two_mass import THESIS, averaging_figure, describe, summarize
    from wrsim.closed_form.two_mass import TwoMassParams
    from wrsim.closed_form.worm_gear import equivalent_mass

    options = {"M1": "m1", "M2": "m2", "c": "c", "mu": "mu", "omega": "omega", "F_a": "fa", "F_r": "fr"}
    summaries = []
    for case in args.case or list(THESIS):
        values = {field: getattr(THESIS[case], field) for field in options}
        values.update({field: getattr(args, opt) for field, opt in options.items() if getattr(args, opt) is not None})
        try:
            params = TwoMassParams(**values)
        except WrsimError as e:
            field = str(e).split(" ", 1)[0]
            raise WrsimError(f"--{options.get(field, field)}: {e}") from None
        summaries.append(summarize(case, params, args.t_end))
    m1 = equivalent_mass(8.0e-6, 73.0, 0.42, 0.02)
    print(
        f"equivalent armature mass (Eq. 3.24, J_a = 8e-6 kg*m^2, i = 73, eta_w = 0.42, r_cd = 0.02 m): M1 = {m1:.4g} kg"
    )
    for s in summaries:
        print("\n".join(describe(s)))
    print(f"plot: {averaging_figure(Path(args.plot), summaries)}")
    return 0


def cmd_list(args: argparse.Namespace) -> int:
    from wrsim.benches import BENCHES

    for b in BENCHES.values():
        print(f"{b.name:28s} {b.entity:30s} {b.description}")
    print("parameter sets: " + ", ".join(sorted(p.stem for p in paths.PARAMS.glob("*.txt"))))
    return 0


def cmd_select_drive(args: argparse.Namespace) -> int:
    from wrsim.backend.ngspice.batch import NgspiceBatch
    from wrsim.benches import BENCHES
    from wrsim.benches.core import bench_params
    from wrsim.benches.system import DRIVE_CLASSES, drive_selection
    from wrsim.data.publish import unique_folder
    from wrsim.elab import load_library

    print(
        drive_selection(
            load_library(paths.LIBRARY),
            bench_params(BENCHES["stroke"], args.params),
            NgspiceBatch(),
            unique_folder(Path(args.results).parent / "work" / "select-drive"),
            args.classes or DRIVE_CLASSES,
        )
    )
    return 0


class _Parser(argparse.ArgumentParser):
    """Usage errors as one `wrsim: error:` line and exit status 2, like every other user error."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"wrsim: error: {self.prog}: {message}\n")


def _finite(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"'{text}' is not a finite number")
    return value


def _positive(text: str) -> float:
    value = _finite(text)
    if value <= 0.0:
        raise argparse.ArgumentTypeError(f"'{text}' must be > 0")
    return value


MAX_T_END = 1000.0  # [s] the averaging plot integrates on a fixed grid; longer spans are not a window stroke


def _t_end(text: str) -> float:
    value = _positive(text)
    if value > MAX_T_END:
        raise argparse.ArgumentTypeError(f"'{text}' is more than {MAX_T_END:g} s")
    return value


_PARAMS_HELP = (
    "parameter set, a name (params/<name>.txt, e.g. antipinch/observer) or a file, laid over the base "
    "set: the bench's, or the one the testbench's header names; repeatable, laid in the order given"
)


def _params(p: argparse.ArgumentParser) -> None:
    """`--params`, the same in every command (benches.core.bench_params)."""
    p.add_argument("--params", action="append", default=[], metavar="SET", help=_PARAMS_HELP)


def _simulation(p: argparse.ArgumentParser, stop: float | None) -> None:
    """The transient analysis and the top-level generics, the same in `wrsim run` and `wrsim lower` (which
    therefore write the same netlist); `stop` None: required."""
    p.add_argument(
        "--stop",
        type=_positive,
        required=stop is None,
        default=stop,
        help="end of the transient analysis [s]" + (f" (default {stop:g})" if stop else ""),
    )
    p.add_argument("--max-step", type=_positive, help="largest step [s] (default: stop / 500)")
    p.add_argument(
        "--reltol",
        type=_positive,
        help="ngspice's relative tolerance (default 1e-4; the closed-loop benches run at 1e-3)",
    )
    p.add_argument(
        "--save",
        nargs="+",
        action="extend",
        metavar="NAME",
        help="quantities and signals to write, by hierarchical name (default: all)",
    )
    p.add_argument(
        "--set",
        type=_generic,
        action="append",
        metavar="GENERIC=VALUE",
        help="top-level generic: a number with or without a unit (u_nominal=9V, pinch_position=320mm), "
        "a string (sequence_file=my/seq.txt, relative to this directory), true/false (repeatable)",
    )


def _count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a whole number") from None
    if value < 2:
        raise argparse.ArgumentTypeError(f"'{text}' must be at least 2")
    return value


def _dask(p: argparse.ArgumentParser, what: str) -> None:
    p.add_argument("--scheduler", help=f"{what} on the Dask scheduler at this address (tcp://host:8786)")
    p.add_argument("--dask-local", type=int, metavar="N", help=f"{what} on a Dask LocalCluster of N worker processes")


def build_parser() -> argparse.ArgumentParser:
    ap = _Parser(prog="wrsim", description="window-regulator simulation toolkit")
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("testbench", help="run benches, write build/results, print pass/fail")
    p.add_argument("--bench", action="append", help="bench name (repeatable; default: all)")
    _params(p)
    p.add_argument("--results", default=str(paths.RESULTS))
    p.add_argument(
        "--c-algorithm",
        help="C file linked into the ECU instead of vhdl/digital/antipinch.c; without "
        "--params the ECU runs it (params/antipinch/c_twin.txt; docs/anti-pinch.md)",
    )
    p.add_argument(
        "--convergence",
        type=float,
        metavar="RELTOL",
        help="also run each bench at this tighter reltol: its page gets every metric at both and the verdicts that "
        "change (a convergence note, e.g. 1e-4 for the closed-loop benches' 1e-3)",
    )
    p.set_defaults(func=cmd_testbench)
    p = sub.add_parser(
        "regression",
        help="every bench's waveforms against its reference inside tolerance tubes "
        "(testbenches/golden/); pages of failing signals in build/results/regression",
    )
    p.add_argument("--bench", action="append", help="bench name (repeatable; default: all)")
    _params(p)
    p.add_argument("--results", default=str(paths.RESULTS))
    p.add_argument("--bless", action="store_true", help="make the results the new references (needs --reason)")
    p.add_argument("--reason", help="with --bless: why the references change (recorded in BLESSINGS.tsv)")
    p.set_defaults(func=cmd_regression)
    p = sub.add_parser(
        "report-check",
        help="open the HTML report in headless Chromium: screenshots, and every "
        "JavaScript error, failed load, broken image and broken link",
    )
    p.add_argument("--results", default=str(paths.RESULTS))
    p.set_defaults(func=cmd_report_check)
    p = sub.add_parser(
        "score",
        help="anti-pinch algorithms on the compliance matrix and the drum bench: worst "
        "peak per regulation, false reversals, latency (build/results/score/)",
    )
    p.add_argument(
        "--algorithm",
        action="append",
        help="parameter set of an algorithm, name or file (repeatable; default: every params/antipinch/*.txt)",
    )
    _params(p)
    p.add_argument(
        "--c-algorithm",
        help="C file that replaces vhdl/digital/antipinch.c: the algorithm c_twin runs "
        "it (scored alone unless --algorithm is given)",
    )
    p.add_argument(
        "--fleet",
        action="append",
        metavar="TOLERANCES",
        help="score on a fleet of doors drawn from these spreads instead (repeatable: tolerances/production "
        "tolerances/ambient); every algorithm replayed on records of the catalog (docs/anti-pinch.md)",
    )
    p.add_argument("--samples", type=int, default=10, help="with --fleet: the number of doors (default 10)")
    p.add_argument("--seed", type=int, default=1, help="with --fleet: the seed of the draws (default 1)")
    p.add_argument(
        "--catalog",
        nargs="+",
        default=[str(paths.SCENARIOS / "catalog")],
        help="with --fleet: scenario files or folders (default testbenches/scenarios/catalog)",
    )
    _dask(p, "with --fleet: record the doors")
    p.add_argument("--results", default=str(paths.RESULTS))
    p.set_defaults(func=cmd_score)
    p = sub.add_parser(
        "run",
        help="simulate your own VHDL-AMS testbench: every saved waveform as CSV, MDF4 and a "
        "plot (results/run/<top>/), with the parameter set its header names (`parameter "
        "set: ...`) and --params over it",
    )
    p.add_argument("files", nargs="+", help="VHDL-AMS files or folders (.vhd, .vhdl, .ams, .vha)")
    p.add_argument("--top", required=True, help="the testbench entity (no ports)")
    _simulation(p, stop=None)
    p.add_argument(
        "--resample", type=_count, metavar="N", help="write N uniform time points instead of the solver's own"
    )
    p.add_argument(
        "--lib",
        type=_library_map,
        action="append",
        metavar="NAME=DIR",
        help="files of library NAME (repeatable); IEEE_PROPOSED is IEEE unless mapped",
    )
    _params(p)
    p.add_argument(
        "--with-models",
        action="store_true",
        help="also load wrsim's model library (vhdl/); a unit of FILES replaces the library's one of the same name",
    )
    p.add_argument("--results", default=str(paths.RESULTS))
    p.set_defaults(func=cmd_run)
    p = sub.add_parser(
        "scenario",
        help="run closed-loop scenario files (TOML, docs/scenarios.md) side by side: a "
        "page per scenario and a summary (results/scenario/); exit 1 on a failure",
    )
    p.add_argument("targets", nargs="+", metavar="FILE|DIR", help="scenario files, or folders of them (*.toml)")
    _params(p)
    p.add_argument("--results", default=str(paths.RESULTS))
    p.set_defaults(func=cmd_scenario)
    p = sub.add_parser(
        "record",
        help="run scenario files in closed loop with the ECU's reversal held off and keep the ECU's inputs and the "
        "gauge force: records that `wrsim replay` plays any algorithm on (docs/anti-pinch.md)",
    )
    p.add_argument("targets", nargs="+", metavar="FILE|DIR", help="scenario files, or folders of them (*.toml)")
    _params(p)
    p.add_argument("--out", default=str(paths.BUILD / "records"), help="folder of the records (default build/records)")
    p.set_defaults(func=cmd_record)
    p = sub.add_parser(
        "replay",
        help="the ECU software alone (GHDL) on records of its inputs: where each anti-pinch algorithm detects "
        "(docs/anti-pinch.md, 'Record and replay')",
    )
    p.add_argument(
        "records",
        nargs="+",
        metavar="RECORD",
        help="record folders of `wrsim record`, folders of them, or input record files of a real door",
    )
    p.add_argument(
        "--algorithm",
        action="append",
        help="parameter set of an algorithm, name or file (repeatable; default: every params/antipinch/*.txt)",
    )
    _params(p)
    p.add_argument("--c-algorithm", help="C file that replaces vhdl/digital/antipinch.c (the algorithm c_twin)")
    p.add_argument(
        "--closed-loop",
        nargs="+",
        metavar="SCENARIOS",
        help="also run each record's scenario (files or folders) in closed loop with each algorithm and compare the "
        "first detections (exit 1 if any differs); C algorithms on cold records only",
    )
    p.set_defaults(func=cmd_replay)
    p = sub.add_parser(
        "calibrate",
        help="search an anti-pinch algorithm's calibration values (declared `in LOW .. HIGH unit calibrate` in its "
        "set) with optuna on replayed records of the catalog's tuning cases over a fleet of doors; resumable",
    )
    p.add_argument("algorithm", help="the algorithm's parameter set, name or file (e.g. observer)")
    p.add_argument(
        "--fleet",
        action="append",
        required=True,
        metavar="TOLERANCES",
        help="spreads the doors are drawn from (repeatable: tolerances/production tolerances/ambient)",
    )
    p.add_argument("--samples", type=int, default=10, help="doors (default 10)")
    p.add_argument("--seed", type=int, default=1, help="seed of the doors and of the search (default 1)")
    p.add_argument("--trials", type=int, default=60, help="optuna trials in all, a resumed study's included")
    p.add_argument("--out", help="the calibrated set (default build/calibrated/<algorithm>.txt)")
    p.set_defaults(func=cmd_calibrate)
    p = sub.add_parser(
        "export",
        help="write a parameter set as VHDL packages (wr_params, wr_digital_params) for "
        "Saber or SystemVision: the set's values in place of the library's defaults",
    )
    _params(p)
    p.add_argument("--bench", help="the set a bench runs with, and its runs' top-level generics in the header")
    p.add_argument("--out", help="folder to write (default: build/export/<bench or set>)")
    p.set_defaults(func=cmd_export)
    p = sub.add_parser(
        "study",
        help="tolerance study of a bench: Monte Carlo, one-at-a-time sensitivity or "
        "worst-case corners over the parameter spreads (docs/tolerance-studies.md)",
    )
    p.add_argument("bench")
    _params(p)
    p.add_argument("--method", choices=["montecarlo", "sensitivity", "worst-case"], default="montecarlo")
    p.add_argument("--samples", type=int, default=100, help="Monte Carlo samples (default 100)")
    p.add_argument("--seed", type=int, default=1, help="seed of the draws (default 1): sample i is always the same")
    p.add_argument("--run", action="append", help="only this run of the bench (repeatable)")
    p.add_argument(
        "--set",
        type=_generic,
        action="append",
        metavar="GENERIC=VALUE",
        help="top-level generic of every run, e.g. u_nominal=9V (repeatable)",
    )
    p.add_argument("--stop", type=_positive, help="end of the transient analysis [s] instead of the bench's")
    p.add_argument(
        "--limit",
        type=_limit,
        action="append",
        help="specification limits of an output, 'OUTPUT=LOW..HIGH' (repeatable)",
    )
    p.add_argument("--workers", type=int, help="local processes (default: one per core)")
    _dask(p, "run the samples")
    p.add_argument("--name", help="the study's folder under results/study/ (default: <bench>-<method>)")
    p.add_argument("--fresh", action="store_true", help="discard the study's earlier samples instead of resuming")
    p.add_argument("--rerun", type=int, metavar="ID", help="run sample ID again with the bench's plots and waveforms")
    p.add_argument("--results", default=str(paths.RESULTS))
    p.set_defaults(func=cmd_study)
    p = sub.add_parser("bench", help="time every bench: wall, lowering and ngspice")
    p.add_argument(
        "--study",
        action="store_true",
        help="time tolerance studies instead (wrsim.study.timing: 1000 "
        "strokes, 100 pinches, local vs Dask with 1 and 2 workers)",
    )
    p.add_argument(
        "--warm",
        action="store_true",
        help="warm starts instead: each warm twin of "
        "testbenches/scenarios/warm/ against its cold bench run (peak "
        "forces, detection, wall time saved)",
    )
    p.add_argument("--bench", action="append")
    _params(p)
    p.add_argument("--results", default=str(paths.RESULTS))
    p.set_defaults(func=cmd_bench)
    p = sub.add_parser("lower", help="print or write the ngspice netlist of a testbench entity")
    p.add_argument("entity")
    _params(p)
    _simulation(p, stop=1.0)
    p.add_argument("-o", "--output")
    p.set_defaults(func=cmd_lower)
    p = sub.add_parser("dump", help="show a front-end stage: tokens or ast of a file, model of an entity")
    p.add_argument("stage", choices=["tokens", "ast", "model"])
    p.add_argument("target", help="a .vhd file (tokens, ast) or a testbench entity (model)")
    _params(p)
    p.set_defaults(func=cmd_dump)
    p = sub.add_parser("check", help="parse and elaborate the library and every bench; lint units")
    _params(p)
    p.set_defaults(func=cmd_check)
    p = sub.add_parser(
        "identify",
        help="identify parameters: default (the thesis data), motor|drive|damper FILES "
        "(raw test-stand CSVs, docs/measurement-format.md), operating-points FILE (a drive from its operating "
        "points in the system, --base FAMILY), temperature (derived set)",
    )
    p.add_argument("what", choices=["default", "motor", "drive", "damper", "operating-points", "temperature"])
    p.add_argument("files", nargs="*", help="raw measurement files (motor, drive, damper)")
    p.add_argument("--out", help="parameter set to write (default for 'default': params/fpg2_12nm.txt)")
    p.add_argument("--report", help="directory for the validation report (index.html, PNGs)")
    p.add_argument("--base", help="parameter set whose other sections are carried over; drive: the motor set")
    p.add_argument("--ratio", type=_positive, help="drive: worm-gear ratio (default: [worm_gear] ratio of --base)")
    p.add_argument(
        "--method",
        choices=["calculator", "least-squares"],
        default="calculator",
        help="motor: parameter calculator on the middle line (thesis) or least squares",
    )
    p.add_argument("--celsius", type=_finite, help="temperature: target temperature in degC (-40 .. 85)")
    p.add_argument(
        "--voltage", type=_positive, default=13.0, help="operating-points: supply voltage of the points [V] (13)"
    )
    p.set_defaults(func=cmd_identify)
    p = sub.add_parser(
        "averaging",
        help="two-mass model (thesis 3.1): groups, existence bound, stationary amplitude, averaged vs exact plot",
    )
    p.add_argument(
        "--case",
        action="append",
        choices=["relative", "m2"],
        help="friction on x2'-x1' (relative) or on x2' (m2); repeatable (default: both thesis cases)",
    )
    for opt, what in (
        ("m1", "M1 [kg]"),
        ("m2", "M2 [kg]"),
        ("c", "stiffness c [N/m]"),
        ("mu", "damping mu [N*s/m]"),
        ("omega", "forcing frequency [1/s]"),
        ("fa", "force amplitude F_a [N]"),
        ("fr", "friction force F_r [N]"),
    ):
        p.add_argument(f"--{opt}", type=_finite, help=f"{what} (default: the thesis case's value)")
    p.add_argument("--t-end", type=_t_end, default=4.0, help=f"integration time [s] (default 4, at most {MAX_T_END:g})")
    p.add_argument("--plot", default=str(paths.BUILD / "averaging.png"), help="PNG to write")
    p.set_defaults(func=cmd_averaging)
    p = sub.add_parser(
        "select-drive",
        help="choose the drive power class for the simulated stroke load "
        "(thesis 5.3.1: working point <= 40 %% of the class torque, -15 %%)",
    )
    _params(p)
    p.add_argument("--classes", type=_positive, nargs="+", help="power classes in N*m (default: 8.5 10 12 13.75)")
    p.add_argument("--results", default=str(paths.RESULTS))
    p.set_defaults(func=cmd_select_drive)
    p = sub.add_parser("list", help="list benches and parameter sets")
    p.set_defaults(func=cmd_list)
    return ap


def main(argv: list[str] | None = None) -> int:
    """Run one command; returns the exit status (2: a user error, one line on stderr; 130: interrupted)."""
    try:
        args = build_parser().parse_args(argv)
        return int(args.func(args))
    except SystemExit as e:  # argparse: --help (0) or a usage error already printed (2)
        return e.code if isinstance(e.code, int) else 2
    except WrsimError as e:
        print(f"wrsim: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("wrsim: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader stopped reading (`wrsim dump model ... | head`): not an error
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except Exception as e:  # noqa: BLE001 - a defect of wrsim: one line, never a traceback
        print(f"wrsim: internal error: {type(e).__name__}: {e} (please report, with the command)", file=sys.stderr)
        return 70


if __name__ == "__main__":
    sys.exit(main())
