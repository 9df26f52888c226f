"""The commands of `wrsim` (cli.py parses their arguments): each takes the parsed arguments, calls the public API,
prints what it found and returns the exit status; a user error is a WrsimError, which `wrsim.cli.main` turns into one
line on stderr and exit status 2."""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import shutil
import sys
import tempfile
from pathlib import Path
from typing import Any

from wrsim import paths
from wrsim.errors import WrsimError

__all__ = [
    "cmd_testbench",
    "cmd_regression",
    "cmd_report_check",
    "cmd_study",
    "cmd_run",
    "cmd_export",
    "cmd_bench",
    "cmd_lower",
    "cmd_dump",
    "cmd_check",
    "cmd_identify",
    "cmd_averaging",
    "cmd_list",
    "cmd_select_drive",
    "dask_client",
]


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
    pages = []  # every page: benches, runs, scenarios, studies, fleets, scores, tables, regression
    for folder, subfolders, files in os.walk(root, followlinks=True):  # a result folder is a link to its version
        subfolders[:] = sorted(d for d in subfolders if not d.startswith((".", "_")) and d != "screenshots")
        pages += [Path(folder) / f for f in sorted(files) if f.endswith(".html")]
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
        client = dask_client(args, stack)
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


def dask_client(args: argparse.Namespace, stack: contextlib.ExitStack) -> Any:
    """The Dask client of `--scheduler ADDRESS` (secured and its workers checked: wrsim.study.cluster) or
    `--dask-local N` (closed with `stack`), None without them."""
    from wrsim.study.cluster import TLS_OPTIONS, check_workers, connect

    tls = {"tls_ca_file": args.tls_ca_file, "tls_client_cert": args.tls_cert, "tls_client_key": args.tls_key}
    if args.scheduler:
        client = stack.enter_context(connect(args.scheduler, tls, args.insecure))
        check_workers(client)
        return client
    given = [flag for field, flag, _ in TLS_OPTIONS if tls[field]] + (["--insecure"] if args.insecure else [])
    if given:
        raise WrsimError(f"{given[0]} goes with --scheduler (a Dask scheduler on another machine)")
    if not args.dask_local:
        return None
    from distributed import Client

    from wrsim.study.engine import local_cluster

    return stack.enter_context(Client(stack.enter_context(local_cluster(args.dask_local))))


def cmd_run(args: argparse.Namespace) -> int:
    from wrsim.benches.run import run_files

    libraries: dict[str, list[str | Path]] = {}
    for name, folder in args.lib or []:
        libraries.setdefault(name, []).append(folder)
    sweep = _sweep(args.dc) if args.dc else None
    ac = _ac(args.ac) if args.ac else None
    if args.noise_input and not args.noise:
        raise WrsimError("wrsim run: --noise-input refers the noise of --noise to a source: give --noise too")
    noise = (
        (args.noise[0], *_ac([_number("--noise", x) for x in args.noise[1:]]), args.noise_input) if args.noise else None
    )
    if args.stop is None and not (args.op or sweep or ac or noise):
        raise WrsimError(
            "wrsim run: give --stop (the end of the transient), --op or --dc (quiescent points), --ac (small signal) "
            "or --noise"
        )
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
        args.timeout,
        args.op,
        sweep,
        ac,
        noise,
    )
    where = Path(args.results) / "run" / result.bench
    if args.op:
        width = max((len(s.name) for s in result.waveforms[1:]), default=0)
        for s in result.waveforms[1:]:
            print(f"{s.name:{width}s}  {s.values[0]:.9g} {s.unit}")
        print(
            f"{args.top}: the quiescent point of {len(result.waveforms) - 1} quantities and signals; results: {where}"
        )
    elif noise:
        print(f"{args.top}: the noise density of {noise[0]}; results: {where} (noise.csv, noise.png)")
    elif ac:
        print(
            f"{args.top}: the small-signal response from {ac[0]:g} to {ac[1]:g} Hz; results: {where} (ac.csv, ac.png)"
        )
    elif sweep:
        print(f"{args.top}: {len(sweep[1])} quiescent points over {sweep[0]}; results: {where} (dc.csv, dc.png)")
    else:
        print(
            f"{args.top}: {len(result.waveforms) - 1} waveforms over {args.stop:g} s "
            f"({len(result.waveforms[0].values)} points); results: {where}"
        )
    return 0


def _number(option: str, text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise WrsimError(f"{option}: '{text}' is not a number") from None


def _ac(spec: list[float]) -> tuple[float, float, int]:
    """`--ac FSTART FSTOP POINTS` (and the frequencies of `--noise`), checked."""
    fstart, fstop, points = spec
    if not (0 < fstart < fstop and math.isfinite(fstop) and points >= 1 and points == int(points) and points <= 1000):
        raise WrsimError(
            f"--ac {' '.join(f'{x:g}' for x in spec)}: needs 0 < FSTART < FSTOP [Hz] and 1 to 1000 POINTS a decade"
        )
    return fstart, fstop, int(points)


def _sweep(spec: list[str]) -> tuple[str, list[float]]:
    """`--dc GENERIC FROM TO STEP`: the generic and its values (FROM, FROM + STEP, ... up to TO, both ends included
    within STEP/1000)."""
    generic, *numbers = spec
    try:
        start, stop, step = (float(x) for x in numbers)
    except ValueError:
        raise WrsimError(f"--dc {' '.join(spec)}: FROM, TO and STEP must be numbers") from None
    count = (stop - start) / step if step else -1.0
    if not (math.isfinite(count) and count >= 0 and count <= 10_000):
        raise WrsimError(
            f"--dc {' '.join(spec)}: STEP must go from FROM to TO in at most 10,000 steps (found {count:g})"
        )
    return generic, [start + k * step for k in range(int(count + 1e-3) + 1)]


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
        for c in warm_checks(unique_folder(paths.beside_results(args.results, "work") / "warm-checks")):
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
    for t in time_benches(benches, args.params, paths.beside_results(args.results, "work")):
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
        out = Path(args.output)
        netlist.write(out)
        if netlist.devices:  # the compiled device beside the netlist, whose .control loads it (pre_osdi)
            from wrsim.backend.ngspice import osdi

            (out.parent / "devices.c").write_text(netlist.devices, encoding="utf-8")
            shutil.copyfile(osdi.build(netlist.devices, paths.NATIVE), out.parent / osdi.LIBRARY_FILE)
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
            unique_folder(paths.beside_results(args.results, "work") / "select-drive"),
            args.classes or DRIVE_CLASSES,
        )
    )
    return 0
