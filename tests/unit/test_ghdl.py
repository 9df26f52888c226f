"""wrsim.backend.ghdl: a digital VHDL unit built with GHDL and run inside ngspice through d_cosim and wrsim's glue.

The unit under test is an edge counter with its own sampling clock; the netlists around it are written by hand
(PWL source -> adc_bridge -> d_cosim -> dac_bridge -> analog nodes), the way the netlist generator will write
them, and ngspice runs once per module for the timing tests."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from wrsim.backend.ghdl.build import CC, GHDL, DigitalBuild, DigitalPort, build, check
from wrsim.backend.ghdl.cosim import (
    RUN_ENV,
    instance_line,
    log_failure,
    model_card,
    preflight,
)
from wrsim.backend.ngspice.raw import read_raw
from wrsim.errors import SourceError, WrsimError

pytestmark = pytest.mark.skipif(
    shutil.which(GHDL) is None or shutil.which(CC) is None,
    reason=f"{GHDL} or {CC} not installed (make setup installs both)",
)

EDGE_COUNTER = """\
-- Test unit: counts rising edges of x while en = '1', sampled by an internal clock (rising clock edges at
-- CLK_US/2 + k*CLK_US); falls counts falling edges of x (an integer output).
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

entity edge_counter is
  generic (
    CLK_US  : positive := 100;    -- [us] period of the sampling clock
    LIMIT   : natural  := 3;      -- [edges] full = '1' from this count on
    FAIL_AT : natural  := 0;      -- [edges] assertion failure when the count reaches it (0 = never)
    NAME    : string   := "ec");  -- [-] label in reports
  port (
    x     : in  std_logic;
    count : out std_logic_vector(3 downto 0);
    en    : in  std_logic;
    full  : out std_logic;
    falls : out natural);
end entity edge_counter;

architecture rtl of edge_counter is
  signal clk : std_logic := '0';
  signal xq  : std_logic := '0';
  signal n   : unsigned(3 downto 0) := (others => '0');
begin
  assert LIMIT <= 15 report "edge_counter: LIMIT must be <= 15, got " & integer'image(LIMIT) severity failure;
  clk <= not clk after (CLK_US * 1 us) / 2;
  sample : process (clk)
    variable nf : natural := 0;
  begin
    if rising_edge(clk) then
      xq <= x;
      if x = '1' and xq = '0' and en = '1' then
        n <= n + 1;
        assert FAIL_AT = 0 or to_integer(n) + 1 /= FAIL_AT
          report NAME & ": edge " & integer'image(FAIL_AT) & " reached" severity failure;
      end if;
      if x = '0' and xq = '1' then
        nf := nf + 1;
      end if;
      falls <= nf;
    end if;
  end process;
  count <= std_logic_vector(n);
  full  <= '1' when to_integer(n) >= LIMIT else '0';
end architecture rtl;
"""
PORTS = [
    DigitalPort("x", "in"),
    DigitalPort("count", "out", 4),
    DigitalPort("en", "in"),
    DigitalPort("full", "out"),
    DigitalPort("falls", "out", 32),
]
# x: rising edges at 0.27, 0.67, 1.07 ms, falling at 0.47, 0.87 ms; en drops at 0.97 ms, so the third rising edge
# is not counted. All off the sampling clocks' edges (0.05 + k*0.1 ms at CLK_US=100, 0.1 + k*0.2 ms at 200).
STIMULUS = """\
vx xa 0 pwl(0 0 0.27m 0 0.2701m 1 0.47m 1 0.4701m 0 0.67m 0 0.6701m 1 0.87m 1 0.8701m 0 1.07m 0 1.0701m 1)
ven ena 0 pwl(0 1 0.97m 1 0.9701m 0)
aadc [xa ena] [d_x d_en] adc
.model adc adc_bridge(in_low=0.4 in_high=0.6)
.model dac dac_bridge(out_low=0 out_high=1 out_undef=0.5)
"""
STOP = 1.3e-3
DELAY = 1e-9  # [s] d_cosim's output delay used here to time edges exactly (the model_card default is 1 us, for
#               stiff plants); dac_bridge adds half its 1 ns rise at 0.5 V


def nodes(prefix: str, port: DigitalPort) -> list[str]:
    """The digital nodes of one port, left index first (MSB first for `downto` and integers)."""
    if port.width == 1:
        return [f"{prefix}_{port.name}"]
    return [f"{prefix}_{port.name}{k}" for k in reversed(range(port.width))]


def counter(
    design: DigitalBuild,
    name: str,
    uid: int,
    generics: dict[str, int | bool | str],
    workdir: Path,
    lazy: tuple[str, ...] = (),
) -> list[str]:
    """The element line, the .model line and a dac_bridge for count, full and the two low bits of falls."""
    inputs = {"x": ["d_x"], "en": ["d_en"]}
    outs = [n for p in design.outputs for n in nodes(name, p)]
    watched = [*nodes(name, PORTS[1]), f"{name}_full", f"{name}_falls1", f"{name}_falls0"]
    return [
        instance_line(name, [n for p in design.inputs for n in inputs[p.name]], outs, f"m{name}"),
        model_card(design, f"m{name}", generics, workdir / f"{name}.args", uid, delay=DELAY, lazy=lazy),
        f"adac{name} [{' '.join(watched)}] [{' '.join(w + '_a' for w in watched)}] dac",
    ]


def ngspice(lines: list[str], workdir: Path, env: dict[str, str] | None = RUN_ENV, stimulus: str = STIMULUS):
    """Run the netlist; (exit status, log, vectors from the raw file or None)."""
    workdir.mkdir(parents=True, exist_ok=True)
    cir, raw = workdir / "netlist.cir", workdir / "waveforms.raw"
    cir.write_text("\n".join(["* wrsim.ghdl test", stimulus, *lines, f".tran 1u {STOP} 0 10u", ".end", ""]))
    proc = subprocess.run(
        ["ngspice", "-b", "-r", str(raw), str(cir)],
        capture_output=True,
        text=True,
        cwd=workdir,
        env={**os.environ, **(env or {})},
        timeout=120,
    )
    return proc.returncode, proc.stdout + proc.stderr, read_raw(raw) if raw.exists() else None


def edges(vectors: dict[str, np.ndarray], node: str) -> list[tuple[float, int]]:
    """(time of the 0.5 V crossing, new level) of an analog node, linearly interpolated."""
    t, v = vectors["time"], vectors[f"v({node})"]
    out = []
    for i in np.nonzero(np.diff(v > 0.5))[0]:
        tc = t[i] + (0.5 - v[i]) * (t[i + 1] - t[i]) / (v[i + 1] - v[i])
        out.append((float(tc), int(v[i + 1] > 0.5)))
    return out


def assert_edges(vectors: dict[str, np.ndarray], expected: dict[str, list[tuple[float, int]]]) -> None:
    """Each digital node's analog copy (<node>_a) changes exactly at the expected (time [ms], level) pairs: at a
    sampling clock edge + d_cosim's delay + half the dac_bridge rise time."""
    for node, want in expected.items():
        got = edges(vectors, f"{node}_a")
        assert [level for _, level in got] == [level for _, level in want], node
        assert [t for t, _ in got] == pytest.approx([t * 1e-3 + DELAY + 0.5e-9 for t, _ in want], abs=20e-9), node


@pytest.fixture(scope="module")
def workdir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("ghdl")


@pytest.fixture(scope="module")
def design(workdir: Path) -> DigitalBuild:
    src = workdir / "edge_counter.vhd"
    src.write_text(EDGE_COUNTER)
    return build("edge_counter", [src], PORTS, workdir / "build")


@pytest.fixture(scope="module")
def run(design: DigitalBuild, workdir: Path):
    """Two instances on the same inputs: ec1 with LIMIT=2, ec2 with LIMIT=1 and a 200 us clock."""
    run_dir = workdir / "run"
    lines = [
        *counter(design, "ec1", 1, {"LIMIT": 2, "NAME": "left door"}, run_dir),
        *counter(design, "ec2", 2, {"LIMIT": 1, "CLK_US": 200}, run_dir),
    ]
    status, log, vectors = ngspice(lines, run_dir)
    assert status == 0 and log_failure(log) is None, log[-3000:]
    return vectors


def test_check_reports_ghdl_version():
    assert check().startswith("GHDL ")


def test_counts_edges_at_its_clock_edges(run):
    # count(0) is the last node of the vector (MSB first): 1 edge at 0.35 ms, 2 at 0.75 ms (full, LIMIT=2); the
    # rising edge at 1.07 ms comes while en = '0'. falls (integer, bit 31 first): 1 at 0.55 ms, 2 at 0.95 ms
    assert_edges(
        run,
        {
            "ec1_count0": [(0.35, 1), (0.75, 0)],
            "ec1_count1": [(0.75, 1)],
            "ec1_count2": [],
            "ec1_count3": [],
            "ec1_full": [(0.75, 1)],
            "ec1_falls0": [(0.55, 1), (0.95, 0)],
            "ec1_falls1": [(0.95, 1)],
        },
    )


def test_second_instance_runs_its_own_generics(run):
    # CLK_US=200: sampling edges at 0.1 + k*0.2 ms. x is high at 0.3 and 0.7 ms (edges counted, full at the
    # first with LIMIT=1), low at 0.5 and 0.9 ms (falls counted), high at 1.1 ms with en = '0' (not counted)
    assert_edges(
        run,
        {
            "ec2_count0": [(0.3, 1), (0.7, 0)],
            "ec2_count1": [(0.7, 1)],
            "ec2_full": [(0.3, 1)],
            "ec2_falls0": [(0.5, 1), (0.9, 0)],
            "ec2_falls1": [(0.9, 1)],
        },
    )


def test_a_lazy_output_is_reported_at_the_end_of_the_analog_step(design: DigitalBuild, workdir: Path):
    # count no analog element reads (in wrsim's netlists: only a digital unit or the event log): its changes do
    # not cut the analog step; they arrive at the end of the step that holds them (.tran's step is 10 us here)
    run_dir = workdir / "lazy"
    lines = counter(design, "ec3", 1, {"LIMIT": 2}, run_dir, lazy=("count",))
    assert (run_dir / "ec3.args").read_text().splitlines()[-2:] == ["+lazy=count", f"+delay={DELAY:g}"]
    status, log, vectors = ngspice(lines, run_dir)
    assert status == 0 and log_failure(log) is None, log[-3000:]
    assert_edges(vectors, {"ec3_full": [(0.75, 1)]})  # not lazy: at its clock edge
    got = edges(vectors, "ec3_count0_a")
    assert [level for _, level in got] == [1, 0]
    late = [t - (want * 1e-3 + DELAY + 0.5e-9) for (t, _), want in zip(got, (0.35, 0.75))]
    assert 1e-6 < late[0] <= 10e-6  # the end of the 10 us step that holds the clock edge
    assert abs(late[1]) <= 20e-9  # full's change at 0.75 ms ends that step: count comes with it


FOLLOWER = """\
-- Test unit: qa follows a (read by no analog element: lazy), qb follows b.
library ieee;
use ieee.std_logic_1164.all;

entity follower is
  port (a, b : in std_logic; qa, qb : out std_logic);
end entity follower;

architecture rtl of follower is
begin
  qa <= a;
  qb <= b;
end architecture rtl;
"""


def follower_run(run_dir: Path, lazy: tuple[str, ...], source: str):
    """The follower unit fed by a digital source (d_source lines: time, a, b); (status, log, vectors)."""
    run_dir.mkdir()
    src = run_dir / "follower.vhd"
    src.write_text(FOLLOWER)
    ports = [DigitalPort("a", "in"), DigitalPort("b", "in"), DigitalPort("qa", "out"), DigitalPort("qb", "out")]
    unit = build("follower", [src], ports, run_dir / "build")
    (run_dir / "ab.txt").write_text(source)
    lines = [
        "asrc [d_a d_b] ab",
        '.model ab d_source(input_file="ab.txt")',
        instance_line("f", ["d_a", "d_b"], ["f_qa", "f_qb"], "mf"),
        model_card(unit, "mf", {}, run_dir / "f.args", 1, delay=DELAY, lazy=lazy),
        "adacf [f_qa f_qb] [f_qa_a f_qb_a] dac",
    ]
    return ngspice(lines, run_dir)


def test_an_input_right_after_a_lazy_change_is_not_lost(workdir: Path):
    # Two inputs 0.5 us apart inside one 10 us analog step (a digital source: no analog breakpoint between them).
    # The first changes the lazy output qa; d_cosim advances to the second input's time before passing it on. A
    # report of qa there made d_cosim cut its step back to that time + delay/3 and drop the input it still held,
    # which XSPICE had already passed and did not pass again: qb never followed b (the lost switch command of
    # docs/performance.md). The glue now holds the lazy report back until the input is in: both arrive together.
    status, log, vectors = follower_run(workdir / "follower", ("qa",), "0 0s 0s\n0.3e-3 1s 0s\n0.3005e-3 1s 1s\n")
    assert status == 0 and log_failure(log) is None, log[-3000:]
    assert_edges(vectors, {"f_qb": [(0.3005, 1)], "f_qa": [(0.3005, 1)]})
    assert "deferred=1 " in log


def test_an_input_lost_next_to_a_reaction_is_an_error(workdir: Path):
    # qa reacts to a (combinational, pausing GHDL) and b comes 0.2 ns after a: the report cannot come early, before
    # the input it reacts to, so d_cosim may drop b; the glue says so and the run fails
    status, log, _ = follower_run(workdir / "reaction", (), "0 0s 0s\n0.3e-3 1s 0s\n0.3000002e-3 1s 1s\n")
    problem = log_failure(log)
    assert (
        problem is not None and "ngghdl: error: the report of an output at t=0.0003 s can make d_cosim drop" in problem
    )


def test_an_output_right_before_an_input_is_reported_early(design: DigitalBuild, workdir: Path):
    # count changes at the clock edge of 0.35 ms (x rose at 0.27 ms) and pauses GHDL; en falls 0.2 ns later (a
    # digital source: no analog breakpoint). A report at 0.35 ms made d_cosim cut its step to after en's fall and
    # drop it, which XSPICE did not pass again: en stayed '1' in the unit and x's edge at 0.67 ms counted. The glue
    # reports count just over delay/3 before en's fall instead (0.14 ns early), so the cut comes before it.
    run_dir = workdir / "early"
    run_dir.mkdir()
    (run_dir / "xen.txt").write_text("0 0s 1s\n0.27e-3 1s 1s\n0.3500002e-3 1s 0s\n0.47e-3 0s 0s\n0.67e-3 1s 0s\n")
    stimulus = 'asrc [d_x d_en] xen\n.model xen d_source(input_file="xen.txt")\n' + STIMULUS.splitlines()[-1]
    status, log, vectors = ngspice(counter(design, "ec4", 1, {"LIMIT": 2}, run_dir), run_dir, stimulus=stimulus)
    assert status == 0 and log_failure(log) is None, log[-3000:]
    assert "early=1 " in log
    assert_edges(vectors, {"ec4_count0": [(0.35, 1)]})  # one edge counted: 0 -> 1, never 2
    assert edges(vectors, "ec4_count1_a") == []


def test_a_lazy_port_must_be_an_output(design: DigitalBuild, workdir: Path):
    with pytest.raises(WrsimError, match=r"d_cosim model 'm': x is not an output port of edge_counter"):
        model_card(design, "m", {}, workdir / "u.args", 1, lazy=("x",))


def test_vhdl_assertion_failure_fails_the_run(design: DigitalBuild, workdir: Path):
    run_dir = workdir / "fail"
    lines = counter(design, "ec1", 1, {"FAIL_AT": 2, "NAME": "left door"}, run_dir)
    status, log, _ = ngspice(lines, run_dir)
    assert status == 1
    problem = log_failure(log)
    assert problem is not None and "(assertion failure): left door: edge 2 reached" in problem
    assert "edge_counter.vhd:35:9:" in problem and "@750us" in problem
    # without NGGHDL_FATAL ngspice finishes with status 0 and frozen outputs; the log still tells
    status, log, _ = ngspice(lines, run_dir, env=None)
    assert status == 0 and "left door: edge 2 reached" in (log_failure(log) or "")


def test_preflight_accepts_good_generics(design: DigitalBuild, workdir: Path):
    preflight(design, {"LIMIT": 2, "NAME": "left door", "CLK_US": 300}, workdir / "pre")


@pytest.mark.parametrize(
    "generics, message",
    [
        ({"NO_SUCH": 1}, "cannot find in top entity generic 'no_such'"),
        ({"LIMIT": -1}, "value not in range for generic 'limit'"),
        ({"LIMIT": 99}, "edge_counter: LIMIT must be <= 15, got 99"),
    ],
)
def test_preflight_reports_ghdls_message(design: DigitalBuild, workdir: Path, generics, message):
    with pytest.raises(WrsimError, match=r"digital unit 'edge_counter' with .* fails before the simulation") as e:
        preflight(design, generics, workdir / "pre")
    assert message in str(e.value)


@pytest.mark.parametrize(
    "ports",
    [
        [PORTS[2], *PORTS[:2], *PORTS[3:]],  # en declared before x
        [*PORTS[:4], DigitalPort("falls", "out", 16)],  # wrong width
        PORTS[:4],  # a port left out
    ],
)
def test_preflight_compares_the_port_map(design: DigitalBuild, workdir: Path, ports):
    declared = DigitalBuild(design.top, design.library, design.loader, ports)
    with pytest.raises(
        WrsimError,
        match=r"GHDL sees the ports \(in x\[1\], in en\[1\], out count\[4\], "
        r"out full\[1\], out falls\[32\]\), the netlist expects",
    ):
        preflight(declared, {}, workdir / "pre")


def test_integer_input_is_refused_by_the_glue(workdir: Path):
    src = workdir / "int_in.vhd"
    src.write_text(
        "entity int_in is\n  port (n : in natural; y : out bit);\nend;\n"
        "architecture a of int_in is\nbegin\n  y <= '1' when n > 2 else '0';\nend;\n"
    )
    unit = build("int_in", [src], [DigitalPort("n", "in", 32), DigitalPort("y", "out")], workdir / "build")
    with pytest.raises(
        WrsimError,
        match=r"ngghdl: error: input port 'n' is an integer: GHDL 2.0 cannot set "
        r"integer signals through VPI; use std_logic_vector",
    ):
        preflight(unit, {}, workdir / "pre")


def test_second_build_is_cached(design: DigitalBuild, workdir: Path, monkeypatch: pytest.MonkeyPatch):
    def no_compiler(*args, **kwargs):
        raise AssertionError(f"compiler run on a cached build: {args}")

    monkeypatch.setattr(subprocess, "run", no_compiler)
    again = build("edge_counter", [workdir / "edge_counter.vhd"], PORTS, workdir / "build")
    assert again == design


def test_analysis_error_names_file_line_col(workdir: Path):
    bad = workdir / "bad_unit.vhd"
    bad.write_text(
        "entity bad_unit is\nend;\narchitecture a of bad_unit is\n  signal s : bit;\nbegin\n  s <= 1;\nend;\n"
    )
    with pytest.raises(SourceError) as e:
        build("bad_unit", [bad], [], workdir / "build")
    assert (e.value.loc.file, e.value.loc.line, e.value.loc.col) == (str(bad), 6, 8)
    assert "can't match integer literal with type bit (analysis of digital unit 'bad_unit')" in str(e.value)


def test_elaboration_error_quotes_ghdl(design: DigitalBuild, workdir: Path):
    with pytest.raises(WrsimError, match=r"elaboration of digital unit 'no_such_top' failed:\n  .*no_such_top"):
        build("no_such_top", [workdir / "edge_counter.vhd"], [], workdir / "build")


def test_model_card_writes_args_file(design: DigitalBuild, workdir: Path):
    args = workdir / "card" / "u7.args"
    line = model_card(design, "mu7", {"LIMIT": 2, "NAME": "a b", "ON": True}, args, 7, vcd=workdir / "u7.vcd")
    assert line == (
        f'.model mu7 d_cosim(simulation="./{design.loader.name}" lib_args=["./mu7_{design.library.name}"] '
        f'sim_args=["edge_counter" "@./u7.args"] delay=1e-06 irreversible=7)'
    )
    assert (args.parent / f"mu7_{design.library.name}").resolve() == design.library.resolve()
    assert args.read_text() == f"-gLIMIT=2\n-gNAME=a b\n-gON=true\n--vcd={workdir / 'u7.vcd'}\n+delay=1e-06\n"


@pytest.mark.parametrize(
    "args_name, uid, message",
    [
        ("Upper.args", 1, r"args file name Upper\.args cannot go on a \.model line"),
        ("u=1.args", 1, r"cannot go on a \.model line"),
        ("u.args", 0, r"irreversible number must be an integer >= 1, got 0"),
    ],
)
def test_model_card_rejects_what_ngspice_would_mangle(design: DigitalBuild, workdir: Path, args_name, uid, message):
    with pytest.raises(WrsimError, match=message):
        model_card(design, "m", {}, workdir / args_name, uid)


def test_instance_line():
    assert instance_line("ecu", ["d_hall", "d_s1", "d_s0"], ["d_up"], "mecu") == "aecu [d_hall d_s1 d_s0] [d_up] mecu"
    assert instance_line("clk", [], ["d_clk"], "mclk") == "aclk null [d_clk] mclk"
    with pytest.raises(WrsimError, match="'d x' is not a plain SPICE name"):
        instance_line("u", ["d x"], [], "m")


@pytest.mark.parametrize(
    "log, found",
    [
        ("Instance: aecu   Message: d_cosim failed to load simulation binary /x/l.so.", "d_cosim failed to load"),
        ("Instance: aecu   Message: Warning: mismatched XSPICE/co-simulator input counts: 17/0.", "input counts"),
        ("Warning: Duplicate value 1 in cm_irreversible() for instance aecu2.", "Duplicate value 1"),
        ("ngghdl: VHDL simulation ended at t=0.5 s with status 0; outputs are frozen from now on", None),
        ("Total analysis time (seconds) = 0.1", None),
    ],
)
def test_log_failure_patterns(log, found):
    problem = log_failure(log)
    assert (problem is None) if found is None else (found in problem)
