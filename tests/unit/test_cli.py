"""The command line: a user error is one `wrsim: error:` line on stderr and exit status 2, never a traceback;
`wrsim testbench` exits 1 when a bench misses its tolerance or cannot be simulated."""

from __future__ import annotations

import dataclasses
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from wrsim import cli, paths
from wrsim.benches import BENCHES
from wrsim.benches.core import Bench, Judgement, Run, metric
from wrsim.errors import WrsimError
from wrsim.results import Signal

ROOT = paths.ROOT
USES = "library IEEE;\nuse IEEE.ELECTRICAL_SYSTEMS.all;\n"


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = cli.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def one_error(code: int, err: str) -> str:
    """The message of a user error: exit status 2 and exactly one `wrsim: error:` line on stderr."""
    assert code == 2, err
    assert err.startswith("wrsim: error: ") and err.count("\n") == 1 and err.endswith("\n"), err
    assert "Traceback" not in err
    return err[len("wrsim: error: ") : -1]


def use_library(monkeypatch, tmp_path: Path, text: str) -> Path:
    """Make the CLI read vhdl/ieee plus `text` (one file) instead of the project library."""
    path = tmp_path / "model.vhd"
    path.write_text(USES + text, encoding="utf-8")
    monkeypatch.setattr(paths, "LIBRARY", (ROOT / "vhdl" / "ieee", path))
    return path


# ------------------------------------------------------------------------------------------------ user errors
def test_unknown_bench_lists_the_benches(capsys):
    code, out, err = run(capsys, "testbench", "--bench", "no-such-bench")
    assert one_error(code, err) == f"unknown bench 'no-such-bench' (benches: {', '.join(BENCHES)})"
    assert out == ""


def test_unknown_parameter_set_lists_the_sets(capsys):
    sets = ", ".join(sorted(p.stem for p in (ROOT / "params").glob("*.txt")))
    code, out, err = run(capsys, "lower", "tb_motor_characteristic", "--params", "no_such_set")
    assert one_error(code, err) == f"unknown parameter set 'no_such_set'; available in {ROOT / 'params'}: {sets}"
    assert out == ""


def test_parameter_key_naming_no_generic_lists_the_generics(capsys, tmp_path):
    pset = tmp_path / "typo.txt"
    pset.write_text("[dcpm_motor]\nkee = 0.02 V*s/rad\n", encoding="utf-8")
    code, _, err = run(capsys, "lower", "tb_motor_characteristic", "--params", str(pset))
    assert one_error(code, err) == (
        f"{pset}:2: [dcpm_motor] kee: dcpm_motor has no generic 'kee' (it has: ke, kt, "
        f"ra, laa, j, visc, mc, omega_threshold, ia0, angle0, omega0)"
    )


def test_unknown_top_generic_lists_the_generics(capsys):
    code, _, err = run(capsys, "lower", "tb_motor_characteristic", "--set", "volts=12")
    assert one_error(code, err) == (
        "--set volts: tb_motor_characteristic has no generic 'volts' "
        "(it has: direction, u_supply, torque_end, ramp_time)"
    )


def test_lower_of_an_entity_with_ports(capsys):
    code, out, err = run(capsys, "lower", "dcpm_motor")
    msg = one_error(code, err)
    assert msg.startswith(f"{ROOT / 'vhdl' / 'drive' / 'dcpm_motor.vhd'}:") and msg.endswith(
        ": top-level entity 'dcpm_motor' must not have ports (it is a bench)"
    )
    assert out == ""


def test_lower_of_a_bad_entity_prints_no_netlist(capsys, monkeypatch, tmp_path):
    path = use_library(
        monkeypatch,
        tmp_path,
        "entity tb_bad is end entity tb_bad;\n"
        "architecture s of tb_bad is\n"
        "  quantity x : real;  -- [1] x\n"
        "  quantity y : real;  -- [1] y\n"
        "begin\n  x == 1.0;\nend architecture s;\n",
    )
    code, out, err = run(capsys, "lower", "TB_Bad", "--params", str(empty_params(tmp_path)))
    assert one_error(code, err) == (
        f"{path}:4:1: architecture s of tb_bad: 1 simultaneous statement(s) for 2 "
        f"unknown(s) (x, y); 1076.1 requires one equation per through quantity, free "
        f"quantity and out quantity port"
    )
    assert out == ""


def test_dump_of_a_malformed_file(capsys, tmp_path):
    bad = tmp_path / "bad.vhd"
    bad.write_text("entity e is\n  generic (a : real := 1.0 $ 2.0);\nend entity e;\n", encoding="utf-8")
    for stage in ("tokens", "ast"):
        code, _, err = run(capsys, "dump", stage, str(bad))
        assert one_error(code, err) == f"{bad}:2:28: unexpected character '$'"


@pytest.mark.parametrize("stage", ["tokens", "ast"])
def test_dump_of_a_missing_file(capsys, tmp_path, stage):
    missing = tmp_path / "missing.vhd"
    code, _, err = run(capsys, "dump", stage, str(missing))
    assert one_error(code, err).startswith(f"{missing}: ")


def test_missing_ngspice_says_what_to_install(capsys, monkeypatch, tmp_path):
    monkeypatch.setenv("PATH", str(tmp_path))  # no ngspice on the PATH
    code, _, err = run(capsys, "testbench", "--bench", next(iter(BENCHES)), "--results", str(tmp_path / "r"))
    assert one_error(code, err) == (
        "ngspice not found: install ngspice >= 46 (on Debian 12: `make setup`, which "
        "installs it from bookworm-backports)"
    )
    assert not (tmp_path / "r").exists()


def test_no_traceback_reaches_the_user(tmp_path):
    bad = tmp_path / "bad.vhd"
    bad.write_text(
        "architecture a of e is\n  quantity q : real;\nbegin\n  b1: block begin end block;\nend architecture a;\n",
        encoding="utf-8",
    )
    wrsim = Path(sys.executable).with_name("wrsim")
    proc = subprocess.run([str(wrsim), "dump", "ast", str(bad)], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr == f"wrsim: error: {bad}:4:7: unsupported construct: block statement\n"


# ------------------------------------------------------------------------------------------------ bench verdicts
TINY = """entity tb_tiny is
  generic (level : real := 2.0);  -- [V] value of x
end entity tb_tiny;
architecture s of tb_tiny is
  quantity x : real;  -- [V] a constant
begin
  {equation};
end architecture s;
"""


def empty_params(tmp_path: Path) -> Path:
    path = tmp_path / "empty.txt"
    path.write_text("# no parameters\n", encoding="utf-8")
    return path


def tiny_bench(tmp_path: Path, reference: float, tolerance: float) -> Bench:
    def judge(bench, sims, table, session):
        waves = sims[0].waves
        metrics = [metric("final x", waves["x"][-1], reference, tolerance, "V")]
        return Judgement(
            metrics=metrics, plots=[], waveforms=[Signal("time", "s", waves.time), Signal("x", "V", waves["x"])]
        )

    return Bench(
        name="tiny",
        entity="tb_tiny",
        description="x == level",
        stop=1e-3,
        max_step=1e-4,
        runs=(Run("one", {}),),
        judge=judge,
        params=str(empty_params(tmp_path)),
    )


@pytest.mark.parametrize("tolerance, code, verdict", [(1.5, 0, "PASS"), (0.5, 1, "FAIL")])
def test_testbench_exit_status_follows_the_tolerance(capsys, monkeypatch, tmp_path, tolerance, code, verdict):
    use_library(monkeypatch, tmp_path, TINY.format(equation="x == level"))
    monkeypatch.setitem(BENCHES, "tiny", tiny_bench(tmp_path, 3.0, tolerance))
    results = tmp_path / "results"
    status, out, err = run(capsys, "testbench", "--bench", "tiny", "--results", str(results))
    assert (status, err) == (code, "")
    finished, _, row, *_ = out.splitlines()  # off a terminal: a line as the bench finishes, then the table
    assert re.fullmatch(rf"tiny: {verdict} in \d+\.\d s", finished) and row.split() == ["tiny", verdict]
    data = json.loads((results / "tiny" / "result.json").read_text(encoding="utf-8"))
    assert data["passed"] is (code == 0)
    assert data["metrics"]["final x"]["value"] == pytest.approx(2.0)


def test_a_bench_that_cannot_be_simulated_keeps_its_last_good_result(capsys, monkeypatch, tmp_path):
    results = tmp_path / "results"
    monkeypatch.setitem(BENCHES, "tiny", tiny_bench(tmp_path, 2.0, 0.1))
    use_library(monkeypatch, tmp_path, TINY.format(equation="x == level"))
    assert run(capsys, "testbench", "--bench", "tiny", "--results", str(results))[0] == 0
    good = (results / "tiny" / "result.json").read_bytes()
    use_library(monkeypatch, tmp_path, TINY.format(equation="x * x == -level"))  # no real solution
    status, out, err = run(capsys, "testbench", "--bench", "tiny", "--results", str(results))
    assert (status, err) == (1, "")
    assert re.fullmatch(r"tiny: error after \d+\.\d s", out.splitlines()[0])
    assert out.splitlines()[2].split() == ["tiny", "FAIL"]
    assert (results / "tiny" / "result.json").read_bytes() == good
    failure = json.loads((results / "tiny.failure.json").read_text(encoding="utf-8"))
    assert failure["passed"] is False and "simulation failed" in failure["error"]
    assert "the latest run" in (results / "index.html").read_text(encoding="utf-8")


def test_a_documented_deviation_is_known_not_failed_and_a_stale_one_is_named(capsys, monkeypatch, tmp_path):
    use_library(monkeypatch, tmp_path, TINY.format(equation="x == level"))
    monkeypatch.setitem(BENCHES, "tiny", tiny_bench(tmp_path, 3.0, 0.5))  # x = 2 V: outside 3 +- 0.5
    known = tmp_path / "known.toml"
    known.write_text(
        '[[deviation]]\nbench = "tiny"\nmetric = "final x"\nreason = "the level is 2 V by design"\n'
        'doc = "docs/anti-pinch.md#checks-so-far"\n',
        encoding="utf-8",
    )
    monkeypatch.setattr(paths, "KNOWN", known)
    results = tmp_path / "results"
    status, out, err = run(capsys, "testbench", "--bench", "tiny", "--results", str(results))
    assert (status, err) == (0, "")
    assert re.fullmatch(r"tiny: KNOWN in \d+\.\d s", out.splitlines()[0])
    assert out.splitlines()[2].split() == ["tiny", "KNOWN"]
    assert "summary: 0 PASS, 1 KNOWN, 0 FAIL, 0 errors, 0 regressions" in out
    assert "KNOWN tiny: final x: the level is 2 V by design (docs/anti-pinch.md#checks-so-far)" in out
    page = (results / "tiny" / "index.html").read_text(encoding="utf-8")
    doc = os.path.relpath(paths.ROOT / "docs" / "anti-pinch.md", results / "tiny")  # the link works from the page
    assert f'<a href="{doc}#checks-so-far">docs/anti-pinch.md#checks-so-far</a>' in page
    monkeypatch.setitem(BENCHES, "tiny", tiny_bench(tmp_path, 2.0, 0.5))  # passes again
    status, out, _ = run(capsys, "testbench", "--bench", "tiny", "--results", str(results))
    assert status == 0 and "tiny: final x passes now: remove its entry from" in out
    known.write_text('[[deviation]]\nbench = "tiny"\nmetric = "final x"\nreason = "r"\ndoc = "docs/nothere.md"\n')
    status, out, err = run(capsys, "testbench", "--bench", "tiny", "--results", str(results))
    assert status == 2 and "deviation 1: 'doc' names docs/nothere.md, which does not exist" in err


def _lowered(capsys, tmp_path: Path, *argv: str) -> str:
    out = tmp_path / f"n{len(list(tmp_path.glob('n*.cir')))}.cir"
    code, _, err = run(capsys, "lower", *argv, "-o", str(out))
    assert code == 0, err
    return out.read_text(encoding="utf-8")


def test_params_lay_in_order_over_the_testbench_set_in_every_command(capsys, tmp_path):
    """Obstacles 4 and 5 of issue 27: --params over the set the testbench names (rail_wr_8p5nm for tb_closed_loop),
    repeatable in order; a set that includes the system set and changes one key is the same as the two laid."""
    observer = _lowered(capsys, tmp_path, "tb_closed_loop", "--params", "antipinch/observer")
    assert (
        _lowered(capsys, tmp_path, "tb_closed_loop", "--params", "rail_wr_8p5nm", "--params", "antipinch/observer")
        == observer
    )
    from wrsim import load_library, run_params
    from wrsim.benches.core import testbench_params

    base = testbench_params(load_library(paths.LIBRARY), "tb_closed_loop")
    assert base == ROOT / "params" / "rail_wr_8p5nm.txt"
    pset = run_params(base, ["antipinch/observer"])
    assert pset.number_in("ecu_software", "algorithm", "1") == 4  # the overlay, over the system set
    assert pset.number_in("top_frame_seal", "position", "m") == 0.37
    one = tmp_path / "ra.txt"
    one.write_text("[dcpm_motor]\nra = 0.61 Ohm\n", encoding="utf-8")
    mine = tmp_path / "mine.txt"
    mine.write_text(f"include {ROOT / 'params' / 'rail_wr_8p5nm.txt'}\n[dcpm_motor]\nra = 0.61 Ohm\n", encoding="utf-8")
    laid = _lowered(capsys, tmp_path, "tb_closed_loop", "--params", str(one))
    assert "0.61" in laid
    assert _lowered(capsys, tmp_path, "tb_closed_loop", "--params", str(mine)).replace(str(mine), "X") == laid.replace(
        str(one), "X"
    )
    code, _, err = run(capsys, "lower", "tb_closed_loop", "--params", "antipinch/observer", "--params", "nothing")
    assert one_error(code, err).startswith("unknown parameter set 'nothing'")


def test_lower_writes_the_netlist_that_run_simulates(capsys, tmp_path, monkeypatch):
    """`wrsim lower` and `wrsim run` of the same testbench with the same options write the same netlist, however the
    files were named."""
    monkeypatch.chdir(ROOT)
    options = ["--stop", "0.05", "--set", "u_supply=12V", "--reltol", "1e-3", "--save", "dut.omega"]
    lowered = _lowered(capsys, tmp_path, "tb_motor_characteristic", *options)
    code, _, err = run(
        capsys,
        "run",
        "testbenches/tb_motor_characteristic.vhd",
        "--with-models",
        "--top",
        "tb_motor_characteristic",
        *options,
        "--results",
        str(tmp_path / "out"),
    )
    assert code == 0, err
    work = max((paths.WORK / "run" / "tb_motor_characteristic").iterdir(), key=os.path.getmtime)
    assert (work / "tb_motor_characteristic" / "netlist.cir").read_text(encoding="utf-8") == lowered
    assert "reltol=0.001" in lowered


def test_every_bench_runs_on_the_set_its_testbench_names():
    """The header of a testbench (`parameter set: ...`) and its benches name the same base set: `wrsim run` and
    `wrsim lower` of the testbench start from the set its benches do."""
    from wrsim import load_library
    from wrsim.benches.core import testbench_params

    lib = load_library(paths.LIBRARY)
    for bench in BENCHES.values():
        named = testbench_params(lib, bench.entity)
        assert named is not None and named.stem == bench.params, bench.name


def test_identify_operating_points_from_the_command_line(capsys, tmp_path):
    csv = str(paths.MEASUREMENTS / "fig5_7_5_8_stroke.csv")
    out = tmp_path / "drive.txt"
    msg = one_error(*run(capsys, "identify", "operating-points", csv, "--out", str(out))[::2])
    assert msg.startswith("identify operating-points: give one CSV of operating points and --base FAMILY")
    assert not out.exists()
    family = str(paths.PARAMS / "fpg2_12nm.txt")
    code, text, _ = run(capsys, "identify", "operating-points", csv, "--base", family, "--out", str(out))
    assert code == 0 and "eta=0.5 (on a bound: eta)" in text and "stall 10.418 N*m" in text
    assert out.read_text().startswith("# wrsim parameter set generated by wrsim.identify; do not edit.")


def test_a_deviation_can_name_the_parameter_sets_it_holds_for(tmp_path):
    """An entry with `params` holds only for those --params sets (named as given, joined by '+'; 'default': none),
    and overrides an entry for every set; a second entry for the same sets is an error naming it."""
    from wrsim.benches.known import deviations, mark, sets_label
    from wrsim.results import Metric

    known = tmp_path / "known.toml"
    entry = '[[deviation]]\nbench = "b"\nmetric = "m"\nreason = "{reason}"\ndoc = "README.md"\n{params}\n'
    known.write_text(
        entry.format(reason="at 20 degC", params='params = "default"')
        + entry.format(reason="hot", params='params = "rail_wr_8p5nm_85c+observer"'),
        encoding="utf-8",
    )
    label = sets_label(["rail_wr_8p5nm_85c", "params/antipinch/observer.txt"])
    assert label == "rail_wr_8p5nm_85c+observer" and sets_label([]) == "default"
    assert deviations(known)[("b", "m")].reason == "at 20 degC"
    assert deviations(known, label)[("b", "m")].reason == "hot"
    assert deviations(known, "rail_wr_8p5nm_m40c") == {}
    failing = Metric("m", 1.0, 0.0, 0.5, "N", False)
    assert mark("b", [failing], "rail_wr_8p5nm_m40c", deviations(known, "rail_wr_8p5nm_m40c"))[0].known == ""
    assert "hot" in mark("b", [failing], label, deviations(known, label))[0].known
    known.write_text(entry.format(reason="all", params="") + entry.format(reason="hot", params='params = "hot"'))
    assert deviations(known, "hot")[("b", "m")].reason == "hot"  # the set's own entry overrides the one for all
    assert deviations(known, "cold")[("b", "m")].reason == "all"
    known.write_text(entry.format(reason="a", params='params = "hot"') * 2, encoding="utf-8")
    with pytest.raises(WrsimError, match="deviation 2: a second entry for b: m \\(hot\\)"):
        deviations(known)


def test_convergence_note_runs_the_bench_at_a_tighter_reltol_and_names_changed_verdicts(capsys, monkeypatch, tmp_path):
    """`--convergence RELTOL` runs each bench again at that tighter tolerance: its page gets every metric at both
    (convergence.csv) and a metric counting the verdicts that change; a tolerance not tighter than the bench's is
    one error."""
    from wrsim.benches.convergence import with_convergence
    from wrsim.results import BenchResult, Metric

    use_library(monkeypatch, tmp_path, TINY.format(equation="x == level"))
    monkeypatch.setitem(BENCHES, "tiny", tiny_bench(tmp_path, 2.0, 0.5))
    results = tmp_path / "results"
    status, out, err = run(capsys, "testbench", "--bench", "tiny", "--results", str(results), "--convergence", "1e-6")
    assert (status, err) == (0, "")
    rows = (results / "tiny" / "convergence.csv").read_text(encoding="utf-8").splitlines()
    assert rows[0] == "metric,unit,reltol 0.0001,reltol 1e-06,difference,verdict 0.0001,verdict 1e-06,same verdict"
    assert rows[1:] == ["final x,V,2,2,+0,PASS,PASS,yes"]
    assert (
        "verdicts that change at reltol 1e-06" in json.loads((results / "tiny" / "result.json").read_text())["metrics"]
    )
    status, _, err = run(capsys, "testbench", "--bench", "tiny", "--results", str(results), "--convergence", "1e-3")
    assert status == 2 and "tighter than the bench's own (tiny: reltol 0.0001)" in err

    def result(peak: float) -> BenchResult:
        metrics = [
            Metric("peak 9 V", 60.0, 50.0, 50.0, "N", True),
            Metric("peak 16 V", peak, 50.0, 50.0, "N", peak <= 100),
        ]
        return BenchResult("b", "", None, [], metrics, [], {}, all(m.passed for m in metrics))

    note = with_convergence(result(98.0), result(102.5), 1e-3, 1e-4)
    assert not note.passed and note.metrics[-1].value == 1.0 and note.metrics[-1].note == "peak 16 V"
    assert note.plots[-1].rows[1] == ["peak 16 V", "N", "98", "102.5", "+4.5", "PASS", "FAIL", "FAIL: it changes"]


def test_a_bench_that_breaks_after_its_work_folder_is_removed_is_one_error_with_its_traceback(
    capsys, monkeypatch, tmp_path
):
    """A defect in a bench whose work folder was removed under it (a user cleaning build/work during a run): the
    bench is an error with the defect named and its traceback written, not a second exception."""
    import shutil

    use_library(monkeypatch, tmp_path, TINY.format(equation="x == level"))
    bench = tiny_bench(tmp_path, 2.0, 0.5)

    def judge(bench, sims, table, session):
        shutil.rmtree(session.workdir)
        raise RuntimeError("a defect")

    monkeypatch.setitem(BENCHES, "tiny", dataclasses.replace(bench, judge=judge))
    status, out, err = run(capsys, "testbench", "--bench", "tiny", "--results", str(tmp_path / "results"))
    assert status == 1 and err == ""
    failure = json.loads((tmp_path / "results" / "tiny.failure.json").read_text(encoding="utf-8"))["error"]
    assert failure.startswith("internal error: RuntimeError: a defect (traceback: ")
    assert "RuntimeError: a defect" in Path(failure.split("traceback: ")[1].rstrip(")")).read_text(encoding="utf-8")


def test_a_bench_writes_nothing_outside_the_results_folder_given(capsys, monkeypatch, tmp_path):
    """`--results DIR` keeps the run folders inside DIR (DIR/work; they went to DIR/../work, another user's folder
    when DIR sits in a shared temporary directory); the default results keep them in the build folder."""
    monkeypatch.setitem(BENCHES, "tiny", tiny_bench(tmp_path, 2.0, 0.1))
    use_library(monkeypatch, tmp_path, TINY.format(equation="x == level"))
    shared = tmp_path / "shared"
    results = shared / "mine"
    assert run(capsys, "testbench", "--bench", "tiny", "--results", str(results))[0] == 0
    assert [p.name for p in shared.iterdir()] == ["mine"]
    assert (results / "work" / "tiny").is_dir()
    assert paths.beside_results(paths.RESULTS, "work") == paths.WORK


def test_listing_the_benches_loads_no_heavy_library_nor_scenario_file():
    """`wrsim list` and the bench registry import neither pint, scipy, matplotlib nor python-can (each loads in
    tenths of a second) and read no scenario file: a bench's runs are built at their first use (LazyRuns)."""
    probe = (
        "import sys\n"
        "from wrsim import cli\n"
        "assert cli.main(['list']) == 0\n"
        "from wrsim.benches import BENCHES\n"
        "built = [b.name for b in BENCHES.values() if getattr(b.runs, '_runs', ()) is not None]\n"
        "heavy = sorted(m for m in ('pint', 'scipy', 'matplotlib', 'can', 'asammdf') if m in sys.modules)\n"
        "print(heavy, 'compliance' in built, 'compliance-pwm' in built)\n"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True).stdout
    assert out.splitlines()[-1] == "[] False False"
    compliance = BENCHES["compliance"]
    assert len(compliance.runs) == 25 and compliance.runs[0].label == compliance.runs[:1][0].label
