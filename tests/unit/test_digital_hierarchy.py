"""Digital units (GHDL, d_cosim) anywhere in the instance tree: inside a structural entity, inside a bench without
ports used as a component, several instances of one unit at different depths with their own generics. The netlist
puts every d_cosim element at its top level on the nodes of its instance (x_<label>.<node>); waveforms are named
by label path.

Closed form (fixtures signals/ and digital_hierarchy/): va = sin(2*pi*10*t) rises through the comparator's 0.5 V
at t = (1/12 + k)/10 s; an edge counter with max_edges = n raises done at its n-th edge, which switches its source
from 1 V to 5 V + code, code = (va > 0.5) + 2."""

from __future__ import annotations

import csv
import dataclasses
import shutil

import numpy as np
import pytest

from conftest import netlist
from wrsim import BENCHES, Analysis, NgspiceBatch, bench_params, elaborate, load_library, lower, paths
from wrsim.backend.ghdl.build import CC, GHDL
from wrsim.backend.reference_solver import flatten
from wrsim.benches.core import simulate_runs
from wrsim.cli import main
from wrsim.errors import SourceError

pytestmark = pytest.mark.skipif(
    shutil.which(GHDL) is None or shutil.which(CC) is None,
    reason=f"{GHDL} or {CC} not installed (make setup installs both)",
)

FILES = ("tests/fixtures/signals", "tests/fixtures/digital_hierarchy")
FIXTURES = paths.ROOT / "tests" / "fixtures" / "digital_hierarchy"
RISING = np.array([(1 / 12 + k) / 10 for k in range(5)])  # [s] va rises through 0.5 V
FALLING = np.array([(5 / 12 + k) / 10 for k in range(5)])  # [s] va falls through 0.5 V
# sample times at least 2 ms away from every crossing (a count reaches the recording within a step of 0.1 ms)
GRID = np.array([t for t in np.linspace(0.001, 0.499, 250) if np.min(np.abs(np.r_[RISING, FALLING] - t)) > 2e-3])


def _sampled(w, name: str) -> np.ndarray:
    return w[name][np.searchsorted(w.time, GRID)]


def _edges() -> np.ndarray:
    """The closed form of a counter: rising edges before each grid time."""
    return np.searchsorted(RISING, GRID).astype(float)


def _source(max_edges: int) -> np.ndarray:
    """The closed form of the source that the counter with `max_edges` switches."""
    on = _edges() >= max_edges
    return np.where(on, 7.0 + (np.sin(2 * np.pi * 10 * GRID) > 0.5), 1.0)


def test_a_unit_inside_a_model_gives_the_flat_waveforms(simulate):
    flat = simulate("tb_counted", 0.5, max_step=1e-4, files=FILES)
    nested = simulate("tb_counted_nested", 0.5, max_step=1e-4, files=FILES)
    for a, b in (("count", "count"), ("done", "cell.done"), ("src.v", "cell.src.v"), ("va", "va")):
        np.testing.assert_allclose(_sampled(nested, b), _sampled(flat, a), atol=1e-9, err_msg=b)
    np.testing.assert_array_equal(_sampled(nested, "count"), _edges())
    np.testing.assert_array_equal(_sampled(nested, "cell.count"), _edges())  # the port's own name
    np.testing.assert_allclose(_sampled(nested, "cell.src.v"), _source(3), atol=1e-6)
    switch_on = nested.time[np.argmax(nested["cell.done"] > 0.5)]
    assert switch_on == pytest.approx(RISING[2], abs=3e-4)


def test_the_netlist_hoists_the_unit_onto_the_nodes_of_its_instance():
    nested = netlist("tb_counted_nested", 0.5, 1e-4, FILES)
    text = nested.text
    assert "a_cell__counter [x_cell.pulse] [x_cell.done count_3 count_2 count_1 count_0] cosim_cell__counter" in text
    assert ".include cell__counter.cosim" in text
    assert "t_counter_cell.vhd:18:12: instance cell.counter of digital unit t_edge_counter" in text
    assert [(u.label, u.entity, u.generics, u.lazy) for u in nested.digital] == [
        ("cell__counter", "t_edge_counter", {"max_edges": 3}, ["count"])
    ]
    # count drives the bench's signal through the cell's port: recorded under the bench's node, no D->A bridge
    assert nested.events["x_cell.count_0__a"] == "count_0" and "a_count_0__dac" not in text
    # the names of a unit in the bench itself stay as they were
    flat = netlist("tb_counted", 0.5, 1e-4, FILES).text
    assert "a_counter [pulse] [done count_3 count_2 count_1 count_0] cosim_counter" in flat
    assert ".include counter.cosim" in flat and "digital units inside models" not in flat


def test_three_instances_at_three_depths_with_their_own_generics(simulate):
    """counter (2 edges) in the bench, cell.counter (4) in a structural entity, inner.cell.counter (1) in a bench
    without ports used as a component, its max_edges mapped down from inner's generic."""
    net = netlist("tb_counted_deep", 0.5, 1e-4, FILES)
    assert {u.label: u.generics for u in net.digital} == {
        "counter": {"max_edges": 2},
        "cell__counter": {"max_edges": 4},
        "inner__cell__counter": {"max_edges": 1},
    }
    w = simulate("tb_counted_deep", 0.5, max_step=1e-4, files=FILES)
    # Every counter sees every edge, also when another unit cuts the step in which it counted (its outputs are
    # then reported again: tools/cosim/ngghdl_glue.c).
    for name in ("count", "count4", "cell.count", "inner.count", "inner.cell.count"):
        np.testing.assert_array_equal(_sampled(w, name), _edges(), err_msg=name)
    for source, n in (("src.v", 2), ("cell.src.v", 4), ("inner.cell.src.v", 1)):
        np.testing.assert_allclose(_sampled(w, source), _source(n), atol=1e-6, err_msg=source)
    for done, n in (("done", 2), ("cell.done", 4), ("inner.cell.done", 1)):
        assert w.time[np.argmax(w[done] > 0.5)] == pytest.approx(RISING[n - 1], abs=3e-4), done


def test_a_save_list_names_nested_signals_by_label_path():
    lib = load_library([paths.VHDL / "ieee", paths.VHDL / "common", *(paths.ROOT / f for f in FILES)])
    design = elaborate(lib, "tb_counted_deep")
    net = lower(design, Analysis(stop=0.5, max_step=1e-4, save=("inner.count", "cell.done")), "deep")
    assert net.events == {f"x_inner.x_cell.count_{k}__a": f"x_inner.count_{k}" for k in range(4)} | {
        "x_cell.done__a": "x_cell.done"
    }
    # the reference solver replays the digital nodes equations read from the same record
    record = next(ln for ln in net.text.splitlines() if ln.startswith("eprvcd ")).split()[1:-2]
    replayed = set(flatten(design).inputs.values())
    assert {"done", "x_cell.done", "x_inner.x_cell.done"} <= replayed <= set(record)


def test_a_real_generic_of_the_enclosing_model_cannot_set_a_units_generic(tmp_path):
    (tmp_path / "cell.vhd").write_text(
        "library IEEE;\nuse IEEE.ELECTRICAL_SYSTEMS.all;\nuse IEEE.std_logic_1164.all;\n"
        "entity real_cell is\n  generic (edges : real := 3.0);\n  port (terminal p : electrical);\n"
        "end entity real_cell;\narchitecture a of real_cell is\n  signal pulse, done : std_logic;\n"
        "  signal count : std_logic_vector(3 downto 0);\n  signal unused : std_logic_vector(1 downto 0);\nbegin\n"
        "  cmp: entity work.t_comparator port map (p => p, q => pulse, code => unused);\n"
        "  counter: entity work.t_edge_counter generic map (max_edges => integer(edges))\n"
        "    port map (pulse => pulse, done => done, count => count);\nend architecture a;\n"
        "library IEEE;\nuse IEEE.ELECTRICAL_SYSTEMS.all;\nentity tb_real_cell is\nend entity tb_real_cell;\n"
        "architecture a of tb_real_cell is\n  terminal a : electrical;\nbegin\n"
        "  cell: entity work.real_cell port map (p => a);\nend architecture a;\n"
    )
    lib = load_library([paths.VHDL / "ieee", paths.ROOT / FILES[0], tmp_path])
    with pytest.raises(
        SourceError,
        match=r"cell.vhd:14:65: generic 'max_edges' of digital unit t_edge_counter: "
        r"GHDL takes .* not its real ones",
    ):
        elaborate(lib, "tb_real_cell")


# ------------------------------------------------------------------------------------------------ closed loop
def _normalization(sims, prefix: str) -> tuple[float, float, float]:
    """(time the ECU is normalized [s], glass position then [m], glass position at the end [m])."""
    w = sims[0].waves
    k = int(np.argmax(w[f"{prefix}normalized"] > 0.5))
    glass = w[f"{prefix}plant.door.pane.pos"]
    return float(w.time[k]), float(glass[k]), float(glass[-1])


def test_the_closed_loop_inside_a_users_bench_normalizes_as_the_bench(tmp_path):
    """tb_wrapped_loop holds tb_closed_loop as cl: the normalization bench's run (its sequence, parameter set,
    reltol 1e-3, max_step 1 ms, 8 s) gives the same normalization, its waveforms under cl."""
    lib = load_library([*paths.LIBRARY, FIXTURES])
    bench = BENCHES["normalization"]
    wrapped = dataclasses.replace(bench, entity="tb_wrapped_loop", save=tuple(f"cl.{s}" for s in bench.save))
    assert (bench.stop, bench.max_step, bench.reltol, bench.params) == (8.0, 1e-3, 1e-3, "rail_wr_8p5nm")
    params = bench_params(bench)
    direct, _ = simulate_runs(bench, lib, params, NgspiceBatch(), tmp_path / "direct")
    inside, _ = simulate_runs(wrapped, lib, params, NgspiceBatch(), tmp_path / "wrapped")
    t_norm, top, end = _normalization(direct, "")
    assert 3.5 < t_norm < 4.5 and top == pytest.approx(0.40, abs=0.01) and abs(end) < 0.005  # the bench itself
    w_norm, w_top, w_end = _normalization(inside, "cl.")
    assert w_norm == pytest.approx(t_norm, abs=1e-3)  # a step of the run (max_step)
    assert w_top == pytest.approx(top, abs=1e-5) and w_end == pytest.approx(end, abs=1e-5)  # reltol of 0.4 m
    assert inside[0].waves["cl.motor_state"][-1] == direct[0].waves["motor_state"][-1]


def test_wrsim_run_takes_a_bench_around_the_closed_loop(tmp_path, capsys, monkeypatch):
    """`wrsim run` with the model library, started in the repository: tb_wrapped_loop (its sequence file a default
    relative to the repository) around tb_closed_loop, its supply set from the command line; the motor starts up
    at once (the normalization sequence)."""
    monkeypatch.chdir(paths.ROOT)
    out = tmp_path / "out"
    argv = [
        "run",
        "testbenches/tb_closed_loop.vhd",
        "tests/fixtures/digital_hierarchy/tb_wrapped_loop.vhd",
        "--with-models",
        "--top",
        "tb_wrapped_loop",
        "--stop",
        "0.3",
        "--max-step",
        "1e-3",
        "--params",
        "rail_wr_8p5nm",
        "--set",
        "u_nominal=16",
        "--results",
        str(out),
    ]
    assert main(argv) == 0, capsys.readouterr().err
    with (out / "run" / "tb_wrapped_loop" / "waveforms.csv").open() as f:
        rows = list(csv.reader(f))
    data = np.array(rows[1:], dtype=float)
    column = {name.rsplit("[", 1)[0]: k for k, name in enumerate(rows[0])}  # name[unit]
    t, state, supply, glass = (
        data[:, column[n]] for n in ("time", "cl.motor_state", "cl.supply.ua", "cl.plant.door.pane.pos")
    )
    assert supply[0] == pytest.approx(16.0, abs=0.3)  # --set reached the supply through cl
    assert state[np.searchsorted(t, 0.1)] == 1.0  # up (the sequence's first command)
    assert glass[-1] > glass[np.searchsorted(t, 0.1)] + 1e-3  # and the glass moves up
