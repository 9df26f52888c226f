"""The anti-pinch workbench's commands of `wrsim` (cli.py parses their arguments): scenario files, the score of the
algorithms (on the compliance bench or over a fleet of doors), record and replay, calibration. Each takes the parsed
arguments, calls the public API, prints what it found and returns the exit status, as wrsim.commands does."""

from __future__ import annotations

import argparse
import contextlib
from pathlib import Path

from wrsim import paths
from wrsim.commands import dask_client
from wrsim.errors import WrsimError

__all__ = ["cmd_score", "cmd_scenario", "cmd_record", "cmd_replay", "cmd_calibrate"]


def cmd_score(args: argparse.Namespace) -> int:
    from wrsim.benches.score import algorithm_sets, score_algorithms
    from wrsim.results import Grid

    if args.fleet:
        return _score_fleet(args)
    if args.ecu != "relay":
        raise WrsimError(
            "--ecu is for --fleet: the compliance bench of the PWM ECU is `wrsim testbench --bench compliance-pwm`"
        )
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
    algorithms = args.algorithm or [p for p in algorithm_sets(args.ecu) if p.stem != "c_twin"]
    with contextlib.ExitStack() as stack:
        client = dask_client(args, stack)
        _, page = score_fleet(
            args.fleet, args.samples, args.seed, args.catalog, algorithms, Path(args.results), client, args.ecu
        )
    grid = page.plots[0]
    assert isinstance(grid, Grid) and grid.columns == SUMMARY_COLUMNS
    _print_table([grid.columns, *grid.rows])
    print(f"results: {Path(args.results) / 'fleet' / 'index.html'}")
    return 0 if page.passed else 1


def cmd_scenario(args: argparse.Namespace) -> int:
    from wrsim.benches.scenario_run import SUMMARY_COLUMNS, run_scenarios, summary_rows

    scenarios, results = run_scenarios(args.targets, args.params, Path(args.results), door=args.door, ecu=args.ecu)
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
    from wrsim.benches.scenario import load_scenarios

    scenarios = load_scenarios(args.targets)  # every file checked before any run
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
        ecu=args.ecu,
    )
    print(", ".join(f"{k} = {v}" for k, v in best.items()))
    print(
        f"objective (worst p99 law-cell peak + 1000 N per failing door and case): tuning {tuned:.1f} N, "
        f"validation {checked:.1f} N"
    )
    print(f"calibrated set: {target}")
    return 0
