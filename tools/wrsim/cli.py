"""`wrsim`: the command line. Every user error is one line on stderr and exit status 2; a bench that misses
its tolerance makes `wrsim testbench` exit 1."""
from __future__ import annotations

import argparse
import re
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from .benches import BENCHES, ROOT, run_bench
from .elaborate import elaborate, load_library
from .errors import WrsimError

__all__ = ["main"]

DEFAULT_PARAMS = "fpg2_12nm"


def _library():
    return load_library([ROOT / "vhdl", ROOT / "testbenches"])


def _params(name: str | None, bench=None):
    """A bench's own parameter set overlaid with the set given on the command line. Outside a bench: the set
    given on the command line alone, else the default set."""
    from .params import find_param_set, load_params
    given = load_params(find_param_set(name, ROOT)) if name else None
    if bench is None:
        return given or load_params(find_param_set(DEFAULT_PARAMS, ROOT))
    base = load_params(find_param_set(bench.params, ROOT))
    return base.overlay(given) if given else base


def _bench_of(entity: str):
    return next((b for b in BENCHES.values() if b.entity == entity), None)


def _benches(names: list[str] | None):
    if not names:
        return list(BENCHES.values())
    unknown = [n for n in names if n not in BENCHES]
    if unknown:
        raise WrsimError(f"unknown bench '{unknown[0]}' (benches: {', '.join(BENCHES)})")
    return [BENCHES[n] for n in names]


def cmd_testbench(args) -> int:
    from .report import format_table, write_bench_result, write_failure, write_index
    from .runner import NgspiceBatch
    runner = NgspiceBatch()
    runner.check()
    lib = _library()
    root = Path(args.results)
    results = []
    for bench in _benches(args.bench):
        try:
            result = run_bench(bench, lib, _params(args.params, bench), runner, root.parent / "work" / bench.name)
            write_bench_result(root, result)
            results.append(result)
        except WrsimError as e:
            write_failure(root, bench.name, str(e))
            results.append({"bench": bench.name, "passed": False, "error": str(e), "metrics": {}})
    index = write_index(root)
    print(format_table(results))
    print(f"results: {index}")
    return 0 if all((r.passed if hasattr(r, "passed") else r["passed"]) for r in results) else 1


def cmd_bench(args) -> int:
    from .runner import NgspiceBatch
    runner = NgspiceBatch()
    runner.check()
    benches = _benches(args.bench)
    t0 = time.perf_counter()
    lib = _library()
    parse = time.perf_counter() - t0
    print(f"parse library: {parse * 1000:.0f} ms")
    print(f"{'bench':28s} {'runs':>4s} {'wall [s]':>9s} {'lower [s]':>10s} {'ngspice [s]':>12s} {'per run [s]':>12s}")
    for bench in benches:
        t0 = time.perf_counter()
        r = run_bench(bench, lib, _params(args.params, bench), runner, Path(args.results).parent / "work" / bench.name)
        wall = time.perf_counter() - t0
        n = len(bench.runs)
        print(f"{bench.name:28s} {n:4d} {wall:9.3f} {r.timings['lower']:10.3f} {r.timings['simulate']:12.3f} "
              f"{wall / n:12.3f}")
        coupling = _coupling(Path(args.results).parent / "work" / bench.name)
        if coupling:
            print(f"{'':28s} {coupling} (simulated {bench.stop:g} s per run)")
    return 0


def _coupling(workdir: Path) -> str:
    """The digital units' coupling overhead summed over a bench's runs, from the `ngghdl stats` lines the glue
    writes to each ngspice.log: ngspice steps seen, events exchanged, wall time spent in GHDL."""
    counts = np.zeros(5)
    total = 0.0
    for log in sorted(workdir.glob("*/ngspice.log")):
        text = log.read_text(encoding="utf-8", errors="replace")
        for m in re.finditer(r"ngghdl stats: step=(\d+) wake=(\d+) in_events=(\d+) out_events=(\d+) "
                             r"ghdl_time=\S+ s wall_in_step=([\d.]+) s", text):
            counts += [float(x) for x in m.groups()]
        total += sum(float(x) for x in re.findall(r"Total analysis time \(seconds\) = ([\d.]+)", text))
    if not counts.any():
        return ""
    steps, _, ins, outs, ghdl = counts
    share = f" ({100 * ghdl / total:.1f} % of {total:.1f} s in ngspice)" if total else ""
    return (f"coupling: {steps:.0f} steps seen by the digital units, {ins:.0f} events in, {outs:.0f} out, "
            f"{ghdl:.2f} s in GHDL{share}")


def cmd_lower(args) -> int:
    from .ngspice import Analysis, lower
    lib = _library()
    overrides = {}
    for item in args.set or []:
        key, _, value = item.partition("=")
        try:
            overrides[key.strip().lower()] = float(value)
        except ValueError:
            raise WrsimError(f"--set {item}: expected generic=number") from None
    design = elaborate(lib, args.entity.lower(), _params(args.params, _bench_of(args.entity.lower())), overrides)
    netlist = lower(design, Analysis(args.stop, args.max_step), args.entity)
    if args.output:
        netlist.write(Path(args.output))
    else:
        sys.stdout.write(netlist.text)
    return 0


def cmd_dump(args) -> int:
    from .lexer import tokenize
    from .parser import parse_file
    if args.stage == "tokens":
        try:
            text = Path(args.target).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as e:
            raise WrsimError(f"{args.target}: cannot read VHDL-AMS source: {e}") from None
        for t in tokenize(text, args.target).tokens:
            print(f"{t.loc}\t{t.kind}\t{t.raw or t.text}")
    elif args.stage == "ast":
        for unit in parse_file(args.target).units:
            print(unit)
    else:
        design = elaborate(_library(), args.target.lower(), _params(args.params, _bench_of(args.target.lower())), {})
        for m in design.models + [design.top]:
            print(f"== {m.key}: architecture {m.arch.name} of {m.entity.name} ({m.arch.loc})")
            for u in m.unknowns.values():
                print(f"  unknown {u.node} [{u.unit or '?'}] {u.role} ({u.loc})")
            for eq in m.equations:
                print(f"  equation {eq.loc} solved for {eq.paired}: {eq.residual}")
            for c in m.children:
                print(f"  instance {c.label}: {c.model.key} {c.ports} {c.params}")
    return 0


def cmd_check(args) -> int:
    from .checks import missing_units
    lib = _library()
    problems = missing_units(lib)
    with tempfile.TemporaryDirectory() as tmp:
        for bench in BENCHES.values():
            for run in bench.runs:
                elaborate(lib, bench.entity, _params(args.params, bench), run.resolved(Path(tmp) / run.label))
    for p in problems:
        print(p)
    print(f"{len(lib.files)} files, {len(lib.entities)} entities, {len(BENCHES)} benches elaborated; "
          f"{len(problems)} unit problem(s)")
    return 1 if problems else 0


def cmd_identify(args) -> int:
    if args.what != "default":
        from .identify import identify_files
        opt = {k: Path(getattr(args, k)) if getattr(args, k) else None for k in ("out", "base", "report")}
        for line in identify_files(args.what, [Path(f) for f in args.files], ratio=args.ratio, method=args.method,
                                   celsius=args.celsius, **opt):
            print(line)
        return 0
    if args.files:
        raise WrsimError("identify default takes no files (it reads params/measurements/)")
    from .identify import write_default_set
    out = Path(args.out) if args.out else ROOT / "params" / f"{DEFAULT_PARAMS}.txt"
    r = write_default_set(ROOT, out)
    v = r["validation"]
    p = r["motor"]
    print(f"motor: ke={p.ke:.6g} V*s/rad kt={p.kt:.6g} N*m/A ra={p.ra:.6g} Ohm visc={p.visc:.6g} N*m*s/rad "
          f"mc={p.mc:.3g} N*m")
    print(f"drive: ratio={r['worm_gear']['ratio']:g} eta={r['worm_gear']['eta']:g} m_gc={r['drive']['m_gc']:.6g} N*m")
    print(f"closed-form errors vs thesis lines: motor speed {v['motor_speed_pct']:.3f} %, current "
          f"{v['motor_current_pct']:.3f} %; drive speed {v['drive_speed_pct']:.3f} %, current "
          f"{v['drive_current_pct']:.3f} %")
    print(f"wrote {out}")
    return 0


def cmd_averaging(args) -> int:
    from .analytic import TwoMassParams, equivalent_mass
    from .benches.two_mass import THESIS, averaging_figure, describe, summarize
    options = {"M1": "m1", "M2": "m2", "c": "c", "mu": "mu", "omega": "omega", "F_a": "fa", "F_r": "fr"}
    if not args.t_end > 0.0:
        raise WrsimError(f"--t-end must be > 0, got {args.t_end:g}")
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
    print(f"equivalent armature mass (Eq. 3.24, J_a = 8e-6 kg*m^2, i = 73, eta_w = 0.42, r_cd = 0.02 m): "
          f"M1 = {m1:.4g} kg")
    for s in summaries:
        print("\n".join(describe(s)))
    print(f"plot: {averaging_figure(Path(args.plot), summaries)}")
    return 0


def cmd_list(args) -> int:
    for b in BENCHES.values():
        print(f"{b.name:28s} {b.entity:30s} {b.description}")
    print("parameter sets: " + ", ".join(sorted(p.stem for p in (ROOT / "params").glob("*.txt"))))
    return 0


def cmd_select_drive(args) -> int:
    from .benches.system import DRIVE_CLASSES, drive_selection
    from .runner import NgspiceBatch
    print(drive_selection(_library(), _params(args.params, BENCHES["stroke"]), NgspiceBatch(),
                          Path(args.results).parent / "work" / "select-drive", args.classes or DRIVE_CLASSES))
    return 0


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="wrsim", description="window-regulator simulation toolkit")
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("testbench", help="run benches, write build/results, print pass/fail")
    p.add_argument("--bench", action="append", help="bench name (repeatable; default: all)")
    p.add_argument("--params", help="parameter set name or file laid over each bench's own set (e.g. a "
                                    "temperature set or an identified drive)")
    p.add_argument("--results", default=str(ROOT / "build" / "results"))
    p.set_defaults(func=cmd_testbench)
    p = sub.add_parser("bench", help="time every bench: wall, lowering and ngspice")
    p.add_argument("--bench", action="append")
    p.add_argument("--params")
    p.add_argument("--results", default=str(ROOT / "build" / "results"))
    p.set_defaults(func=cmd_bench)
    p = sub.add_parser("lower", help="print or write the ngspice netlist of a testbench entity")
    p.add_argument("entity")
    p.add_argument("--params")
    p.add_argument("--stop", type=float, default=1.0)
    p.add_argument("--max-step", type=float, default=None)
    p.add_argument("--set", action="append", help="top-level generic, e.g. --set direction=-1")
    p.add_argument("-o", "--output")
    p.set_defaults(func=cmd_lower)
    p = sub.add_parser("dump", help="show a front-end stage: tokens or ast of a file, model of an entity")
    p.add_argument("stage", choices=["tokens", "ast", "model"])
    p.add_argument("target", help="a .vhd file (tokens, ast) or a testbench entity (model)")
    p.add_argument("--params")
    p.set_defaults(func=cmd_dump)
    p = sub.add_parser("check", help="parse and elaborate the library and every bench; lint units")
    p.add_argument("--params")
    p.set_defaults(func=cmd_check)
    p = sub.add_parser("identify", help="identify parameters: default (the thesis data), motor|drive|damper FILES "
                                        "(raw test-stand CSVs, docs/measurement-format.md), temperature (derived set)")
    p.add_argument("what", choices=["default", "motor", "drive", "damper", "temperature"])
    p.add_argument("files", nargs="*", help="raw measurement files (motor, drive, damper)")
    p.add_argument("--out", help="parameter set to write (default for 'default': params/fpg2_12nm.txt)")
    p.add_argument("--report", help="directory for the validation report (index.html, PNGs)")
    p.add_argument("--base", help="parameter set whose other sections are carried over; drive: the motor set")
    p.add_argument("--ratio", type=float, help="drive: worm-gear ratio (default: [worm_gear] ratio of --base)")
    p.add_argument("--method", choices=["calculator", "least-squares"], default="calculator",
                   help="motor: parameter calculator on the middle line (thesis) or least squares")
    p.add_argument("--celsius", type=float, help="temperature: target temperature in degC (-30 .. 80)")
    p.set_defaults(func=cmd_identify)
    p = sub.add_parser("averaging", help="two-mass model (thesis 3.1): groups, existence bound, stationary "
                                         "amplitude, averaged vs exact plot")
    p.add_argument("--case", action="append", choices=["relative", "m2"],
                   help="friction on x2'-x1' (relative) or on x2' (m2); repeatable (default: both thesis cases)")
    for opt, what in (("m1", "M1 [kg]"), ("m2", "M2 [kg]"), ("c", "stiffness c [N/m]"), ("mu", "damping mu [N*s/m]"),
                      ("omega", "forcing frequency [1/s]"), ("fa", "force amplitude F_a [N]"),
                      ("fr", "friction force F_r [N]")):
        p.add_argument(f"--{opt}", type=float, help=f"{what} (default: the thesis case's value)")
    p.add_argument("--t-end", type=float, default=4.0, help="integration time [s] (default 4)")
    p.add_argument("--plot", default=str(ROOT / "build" / "averaging.png"), help="PNG to write")
    p.set_defaults(func=cmd_averaging)
    p = sub.add_parser("select-drive", help="choose the drive power class for the simulated stroke load "
                                            "(thesis 5.3.1: working point <= 40 %% of the class torque, -15 %%)")
    p.add_argument("--params", help="system parameter set (default: the stroke bench's)")
    p.add_argument("--classes", type=float, nargs="+", help="power classes in N*m (default: 8.5 10 12 13.75)")
    p.add_argument("--results", default=str(ROOT / "build" / "results"))
    p.set_defaults(func=cmd_select_drive)
    p = sub.add_parser("list", help="list benches and parameter sets")
    p.set_defaults(func=cmd_list)
    return ap


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except WrsimError as e:
        print(f"wrsim: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
