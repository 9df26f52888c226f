"""`wrsim`: the command line's arguments; the commands (wrsim.commands) print, the public API does the work. Every
user error is one line on stderr and exit status 2; a bench that misses its tolerance (not a documented deviation,
KNOWN) or leaves its waveform tubes makes `wrsim testbench` exit 1."""

from __future__ import annotations

import argparse
import math
import os
import sys
from typing import NoReturn

from wrsim import paths
from wrsim.antipinch_commands import cmd_calibrate, cmd_record, cmd_replay, cmd_scenario, cmd_score
from wrsim.commands import (
    cmd_averaging,
    cmd_bench,
    cmd_check,
    cmd_dump,
    cmd_export,
    cmd_identify,
    cmd_list,
    cmd_lower,
    cmd_regression,
    cmd_report_check,
    cmd_run,
    cmd_select_drive,
    cmd_study,
    cmd_testbench,
)
from wrsim.errors import WrsimError

__all__ = ["main", "build_parser"]


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


def _library_map(text: str) -> tuple[str, str]:
    name, eq, folder = text.partition("=")
    if not eq or not name.strip() or not folder.strip():
        raise argparse.ArgumentTypeError(f"'{text}': write NAME=DIR (e.g. ieee_proposed=./ieee)")
    return name.strip().lower(), folder.strip()


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
    """`--params` (benches.core.bench_params) and `--compile`, the same in every command."""
    p.add_argument("--params", action="append", default=[], metavar="SET", help=_PARAMS_HELP)
    p.add_argument(
        "--compile",
        action=argparse.BooleanOptionalAction,
        help="the equations as compiled device code that ngspice loads through OSDI, or (--no-compile) as "
        "behavioural sources (default: the setting WRSIM_COMPILE, else compiled; docs/performance.md)",
    )


def _ecu(p: argparse.ArgumentParser, what: str, default: str | None = "relay") -> None:
    """`--ecu`: one of the ECU concepts (benches.scenario.ECUS)."""
    p.add_argument("--ecu", choices=("relay", "pwm"), default=default, help=what)


def _simulation(p: argparse.ArgumentParser, stop: float | None) -> None:
    """The transient analysis and the top-level generics, the same in `wrsim run` and `wrsim lower` (which
    therefore write the same netlist); `stop` None: no default (`wrsim run` asks for it unless --op or --dc)."""
    p.add_argument(
        "--stop",
        type=_positive,
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
    p.add_argument(
        "--scheduler",
        help=f"{what} on the Dask scheduler at this address: tls://host:8786 with certificates (--tls-*), or "
        "tcp://127.0.0.1:8786 on this machine (docs/tolerance-studies.md)",
    )
    p.add_argument("--dask-local", type=int, metavar="N", help=f"{what} on a Dask LocalCluster of N worker processes")
    p.add_argument(
        "--tls-ca-file",
        metavar="PEM",
        help="with a tls:// --scheduler: the CA certificate the cluster's certificates are signed with "
        "(default: the Dask config's distributed.comm.tls.ca-file)",
    )
    p.add_argument(
        "--tls-cert",
        metavar="PEM",
        help="with a tls:// --scheduler: this client's certificate (default: distributed.comm.tls.client.cert)",
    )
    p.add_argument(
        "--tls-key",
        metavar="PEM",
        help="with a tls:// --scheduler: the private key of --tls-cert unless that file holds it (default: "
        "distributed.comm.tls.client.key)",
    )
    p.add_argument(
        "--insecure",
        action="store_true",
        help="allow a plain tcp:// --scheduler on another machine: the tasks (pickled code) travel unencrypted "
        "and unauthenticated",
    )


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
    _ecu(p, "with --fleet: record the closings with this ECU concept (default relay; its records kept apart)")
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
        "--timeout",
        type=_positive,
        default=600.0,
        metavar="S",
        help="wall time [s] the simulation may take; then it is stopped with an error (default 600)",
    )
    analysis = p.add_mutually_exclusive_group()
    analysis.add_argument(
        "--op", action="store_true", help="the quiescent point instead of a transient: every quantity's value"
    )
    analysis.add_argument(
        "--dc",
        nargs=4,
        metavar=("GENERIC", "FROM", "TO", "STEP"),
        help="a quiescent point per value of a top-level generic from FROM to TO by STEP (in the unit of its "
        "subtype): the quantities over the generic (a DC sweep)",
    )
    analysis.add_argument(
        "--ac",
        nargs=3,
        type=float,
        metavar=("FSTART", "FSTOP", "POINTS"),
        help="the small-signal response from FSTART to FSTOP [Hz] (POINTS a decade) around the quiescent point to the "
        "spectrum source quantities: magnitude and phase of every quantity (ac.csv, ac.png)",
    )
    analysis.add_argument(
        "--noise",
        nargs=4,
        metavar=("QUANTITY", "FSTART", "FSTOP", "POINTS"),
        help="the noise density the noise source quantities give QUANTITY (by hierarchical name) from FSTART to "
        "FSTOP [Hz], POINTS a decade (noise.csv, noise.png)",
    )
    p.add_argument(
        "--noise-input",
        metavar="SOURCE",
        help="with --noise: the density also referred to the spectrum source quantity SOURCE (the output's divided "
        "by the gain from SOURCE; a second column of noise.csv)",
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
    p.add_argument(
        "--door",
        metavar="SET",
        help="a set the scenarios start from, beneath their own sets (what a case states holds over it): a fleet "
        "door's door.txt, to run a case as `wrsim score --fleet` recorded it",
    )
    _ecu(
        p,
        "run every scenario with this ECU concept instead of its own `ecu` (relay, the thesis's; pwm, the "
        "H-bridge with speed control, params/ecu/pwm.txt)",
        default=None,
    )
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
    _ecu(p, "the ECU concept the doors' closings are recorded with (default relay)")
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
    p.add_argument(
        "-o", "--output", help="the netlist file (with --compile also the device's C source and library beside it)"
    )
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
        if getattr(args, "compile", None) is None:
            return int(args.func(args))
        from wrsim.backend.ngspice.netlist import compiled_setting

        with compiled_setting(args.compile):  # for this command and the workers it starts
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
