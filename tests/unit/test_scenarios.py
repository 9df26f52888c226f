"""Scenario files (benches.scenario): what a valid file becomes (testbench generics, parameter layers, the switch
sequence with glass heights in metres of glass), and one error naming file:line for each kind of mistake."""

from __future__ import annotations

from pathlib import Path

import pytest

from wrsim import cli, paths
from wrsim.benches import BENCHES
from wrsim.benches.scenario import (
    find_scenarios,
    load_scenario,
    own_sets,
    scenario_params,
    scenario_run,
    write_sequence,
)
from wrsim.errors import WrsimError

GOOD = """\
# a rod right after a start
purpose = "a 65 N/mm rod 20 mm above the glass, closing at 16 V"
params = ["antipinch/observer"]
stop = 4.0

[start]
state = "warm"
glass = "250 mm"

[supply]
nominal = "13 V"

[switch]
units = [
  { at = 0.0, command = "stop" },
  { at = 0.5, command = "up", supply = 16.0 },
  { glass = 0.1, supply = "9 V", timeout = 0.2 },
]

[obstacle]
stiffness = "65 N/mm"
gap = 100e-3

[ambient]
temperature = "-30 degC"

[generics]
drum_diameter = "46 mm"

[expect]
closings = 1
reversal = true
peak_max = "100 N"
"""


class _Fixed:
    """A stand-in for the normalization run of a warm start (benches.scenario.Learning)."""

    def generics(self, s, pset):
        return {"glass_start": s.glass0}

    def below_top(self, s, pset, glass):
        return 1.5 - glass


def write(tmp_path: Path, text: str, name: str = "case.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_a_scenario_becomes_generics_layers_and_a_sequence(tmp_path):
    s = load_scenario(write(tmp_path, GOOD))
    assert (s.name, s.warm, s.glass0, s.stop, s.reversal, s.peak_max, s.closings) == (
        "case",
        True,
        pytest.approx(0.25),
        4.0,
        True,
        100.0,
        1,
    )
    assert s.values == {"u_nominal": 13.0, "gauge_stiffness": pytest.approx(65e3)}
    assert s.params == (paths.ALGORITHMS / "observer.txt",)
    ambient = own_sets(s)[-1]
    assert ambient.sections["ambient"]["temperature"].line == 25  # errors name the scenario's line
    base = scenario_params()
    run = scenario_run(s, base, learning=_Fixed())
    assert run.generics["pinch_position"] == pytest.approx(0.37 - 0.100)
    assert run.generics["drum_diameter"] == pytest.approx(0.046)
    assert run.generics["glass_start"] == pytest.approx(0.25)
    sequence = Path(run.resolved(tmp_path / "run")["sequence_file"]).read_text(encoding="utf-8").splitlines()
    # glass heights on the scale of the normalization run
    assert sequence[1:] == ["T 0.0 0 0.0", "T 0.5 1 3.0", "P 1.4 -4.0 0 0.2   # glass to 0.1 m"]
    # without one, below the glass closed in the frame (0.37 m + 3 x 10 mm)
    sequence = write_sequence(s, base, tmp_path / "seq.txt").read_text(encoding="utf-8").splitlines()
    assert sequence[3] == "P 0.30000000000000004 -4.0 0 0.2   # glass to 0.1 m"
    assert run.parameters(base).number_in("ecu_software", "algorithm", "1") == 4  # the observer, at -30 degC:
    assert run.parameters(base).number_in("bowden", "mu", "1") == pytest.approx(0.20)  # Fig. 4.50's cold bowden


def test_the_users_sets_go_over_the_scenarios_own(tmp_path):
    s = load_scenario(write(tmp_path, GOOD))
    user = write(tmp_path, "[ecu_software]\nalgorithm = 0 1\n", "mine.txt")
    pset = scenario_run(s, scenario_params([user]), learning=_Fixed()).parameters(scenario_params([user]))
    assert pset.number_in("ecu_software", "algorithm", "1") == 0


def _error(tmp_path: Path, text: str) -> str:
    with pytest.raises(WrsimError) as e:
        load_scenario(write(tmp_path, text))
    return str(e.value).replace(str(tmp_path / "case.toml"), "F")


@pytest.mark.parametrize(
    "change, message",
    [
        (("stop = 4.0", "stop = 4.0\ncolour = 1"), "F:5: unknown key 'colour'"),
        (('nominal = "13 V"', 'nominal = "13 V"\nvoltage = 3'), "F:12: [supply] unknown key 'voltage' (keys: nominal)"),
        (('nominal = "13 V"', 'nominal = "thirteen"'), "F:11: [supply] nominal: the generic is a number (real in V)"),
        (('nominal = "13 V"', 'nominal = "13 m"'), "F:11: [supply] nominal: cannot convert 'm'"),
        (("stop = 4.0", "stop = -1"), "F:4: stop: must be > 0"),
        (('state = "warm"', 'state = "hot"'), "F:7: [start] state: 'cold'"),
        (('state = "warm"', 'state = "cold"'), "F:8: [start] glass: a cold start begins at the bottom"),
        (("gap = 100e-3", "gap = 100e-3\nposition = 0.3"), "F:22: [obstacle] give gap or position, not both"),
        (('stiffness = "65 N/mm"\n', ""), "F:20: [obstacle] stiffness: missing"),
        (
            ('"antipinch/observer"', '"antipinch/nothing"'),
            "F:3: params: antipinch/nothing: parameter-set file not found",
        ),
        (('command = "up"', 'command = "upward"'), "F:16: [switch] unit 2: command 'upward': one of stop, up, down"),
        (("at = 0.5", "at = 0.0"), "F:16: [switch] unit 2: at = 0 s: times must be >= 0 and rise"),
        (("timeout = 0.2", "timeout = 0.2, speed = 3"), "F:17: [switch] unit 3: unknown key 'speed'"),
        (("reversal = true", "reversal = 1"), "F:32: [expect] reversal: true"),
        (
            (
                'purpose = "a 65 N/mm rod 20 mm above the glass, closing at 16 V"',
                'purpose = """\nline one\nline two"""',
            ),
            "F:2: purpose: one line",
        ),
        (("[supply]", "[supply"), "F:10:8: not valid TOML: Expected ']'"),
        (('drum_diameter = "46 mm"', 'drum_size = "46 mm"'), None),
    ],
)
def test_a_mistake_is_one_error_with_file_and_line(tmp_path, change, message):
    text = GOOD.replace(*change)
    if message is None:  # found when the run is made: the [generics] key names no generic
        with pytest.raises(WrsimError, match=r"case.toml:28: \[generics\] drum_size: tb_closed_loop has no generic"):
            scenario_run(load_scenario(write(tmp_path, text)), scenario_params(), learning=_Fixed())
        return
    assert _error(tmp_path, text).startswith(message)


def test_a_glass_height_outside_the_stroke_is_named_at_its_unit(tmp_path):
    s = load_scenario(write(tmp_path, GOOD.replace("glass = 0.1,", "glass = 0.5,")))
    run = scenario_run(s, scenario_params(), learning=_Fixed())
    with pytest.raises(WrsimError, match=r"case.toml:17: \[switch\] unit 3: glass 0.5 m is outside the stroke 0 .. "):
        run.resolved(tmp_path / "run")


def test_find_scenarios_takes_files_and_folders(tmp_path):
    write(tmp_path, GOOD, "a.toml")
    write(tmp_path, GOOD, "b.toml")
    assert [p.name for p in find_scenarios([tmp_path])] == ["a.toml", "b.toml"]
    with pytest.raises(WrsimError, match="two scenarios are named a"):
        find_scenarios([tmp_path, tmp_path / "a.toml"])
    with pytest.raises(WrsimError, match="no such scenario file or folder"):
        find_scenarios([tmp_path / "c.toml"])


def test_every_shipped_scenario_loads_under_its_own_name():
    # `wrsim scenario testbenches/scenarios` takes the cases, the catalog, the compliance runs and the warm twins
    # at once; a name twice would stop it
    shipped = [load_scenario(f) for f in find_scenarios([paths.ROOT / "testbenches" / "scenarios"])]
    assert len({s.name for s in shipped}) == len(shipped) > 140


def test_the_scenario_units_are_the_testbench_generics_units():
    """A bare number in a scenario is in the unit of the generic's subtype in tb_closed_loop (one home: the VHDL)."""
    from wrsim import load_library
    from wrsim.benches.scenario import TESTBENCH, unit_table
    from wrsim.elab.context import Context

    lib = load_library(paths.LIBRARY)
    ent = lib.entity(TESTBENCH)
    scope = Context(lib).unit_scope(ent.uses)
    declared = {g.name: g.unit or getattr(scope.lookup(g.type_mark), "unit", None) or "1" for g in ent.generics}
    for generic, unit in unit_table().items():
        assert declared[generic] == unit, generic


def test_the_compliance_bench_has_45_law_cells():
    """FMVSS 118 S5 as written: the 65 N/mm rod satisfies "not less than 20 N/mm" above 25 mm, so it is a law
    cell at every gap; the 20 N/mm rod at 25 mm and below is not (65 N/mm asked): 15 rods x 3 supplies."""
    from wrsim.benches.closed_loop import regulation

    cells = {(k, g): regulation(k, g) for k in (10, 20, 65) for g in (4, 10, 25, 50, 100, 200)}
    assert 3 * sum(law is not None for law in cells.values()) == 45
    assert cells[(65, 200)] == cells[(20, 50)] == "FMVSS 118" and cells[(10, 4)] == "ECE R21"
    assert cells[(20, 25)] is None and regulation(10, 250) is None


def test_the_compliance_bench_runs_its_scenario_files():
    bench = BENCHES["compliance"]
    folder = paths.SCENARIOS / "compliance"
    assert sorted(r.label for r in bench.runs) == sorted(p.stem for p in folder.glob("*.toml"))
    rod = next(r for r in bench.runs if r.label == "65npmm_25mm")
    assert (rod.generics["gauge_stiffness"], rod.generics["pinch_position"]) == (65e3, 0.37 - 25e-3)


def test_bad_scenario_file_on_the_command_line_writes_nothing(tmp_path, capsys):
    bad = write(tmp_path, GOOD.replace("stop = 4.0", 'stop = "soon"'))
    code = cli.main(["scenario", str(bad), "--results", str(tmp_path / "out")])
    _, err = capsys.readouterr()
    assert code == 2 and err.count("\n") == 1 and "case.toml:4: stop" in err, err
    assert not (tmp_path / "out").exists()


def test_a_missing_door_on_the_command_line_is_one_error_and_writes_nothing(tmp_path, capsys):
    good = write(tmp_path, GOOD)
    code = cli.main(["scenario", str(good), "--door", str(tmp_path / "door.txt"), "--results", str(tmp_path / "out")])
    _, err = capsys.readouterr()
    assert code == 2 and err.count("\n") == 1 and "door.txt: parameter-set file not found" in err, err
    assert not (tmp_path / "out").exists() and not (tmp_path / "work").exists()


def test_a_rod_too_stiff_for_any_test_device_is_the_gauges_error_not_the_solvers(tmp_path: Path) -> None:
    """Found by make fuzz's scenario runs: `stiffness = "2147483648 N/mm"` reached ngspice, which stopped with
    "timestep too small" at 0.05 s; the gauge's generic assertion now bounds it at 1000 N/mm (the rail stop's rigid
    1e6 N/m): one error at the model's line, at elaboration, before any transient."""
    from wrsim.elab import elaborate, load_library

    (tmp_path / "tb_rod.vhd").write_text(
        "library IEEE;\nuse IEEE.MECHANICAL_SYSTEMS.all;\nentity tb_rod is\n  generic (k : real := 65.0e3);\n"
        "end entity tb_rod;\narchitecture a of tb_rod is\n  terminal g : translational_v;\n  quantity f : real;\n"
        "begin\n  rod : entity work.antipinch_gauge generic map (stiffness => k)\n"
        "    port map (glass => g, frame => translational_v_ref, pinch_force => f);\nend architecture a;\n",
        encoding="utf-8",
    )
    lib = load_library([*paths.LIBRARY, tmp_path])
    elaborate(lib, "tb_rod", None, {"k": 1.0e6})
    with pytest.raises(WrsimError, match=r"antipinch_gauge\.vhd:\d+:\d+: antipinch_gauge: stiffness must be > 0 and"):
        elaborate(lib, "tb_rod", None, {"k": 2.147483648e12})
