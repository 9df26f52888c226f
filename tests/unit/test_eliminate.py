"""The elimination pass (wrsim.elab.eliminate): explicitly solved free quantities leave the simulator's unknowns
but stay observable, with the values their equations give; what cannot be eliminated stays an unknown."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import wrsim
from conftest import ROOT
from wrsim.elab import symbolic as sy
from wrsim.elab.eliminate import SMALL, eliminated

USES = "library IEEE;\nuse IEEE.MATH_REAL.all;\n"
# x'dot == -x/tau from x(0) = 1: x = exp(-t/tau). y and z are explicit in x; w is an alias chain through y.
DECAY = """
entity tb is
  generic (tau : real := 0.2; k : real := 3.0);  -- [s] time constant, [1] gain
end entity tb;
architecture s of tb is
  quantity x : real;   -- [1] decaying state
  quantity y : real;   -- [1] explicit in x, read by w
  quantity w : real;   -- [1] alias of y
  quantity z : real;   -- [1] explicit in x, read nowhere
begin
  if domain = quiescent_domain use
    x == 1.0;
  else
    x'dot == -x / tau;
  end use;
  y == k * x + 1.0;
  w == y;
  z == x * x;
end architecture s;
"""
# A child whose explicit quantity depends on a generic the parent maps: the probe needs the mapped value.
CHILD = """
entity scaled is
  generic (gain : real := 1.0);
  port (quantity u : in real; quantity v : out real);
end entity scaled;
architecture a of scaled is
  quantity inner : real;   -- [1] explicit, read nowhere
begin
  inner == gain * u;
  v == u;
end architecture a;
entity tb2 is
end entity tb2;
architecture s of tb2 is
  quantity p : real;   -- [1] source
  quantity q : real;   -- [1] child output
begin
  p == 2.0 + now;
  c1: entity work.scaled generic map (gain => 5.0) port map (u => p, v => q);
end architecture s;
"""


def design(tmp_path: Path, text: str, top: str):
    path = tmp_path / "model.vhd"
    path.write_text(USES + text, encoding="utf-8")
    return wrsim.elaborate(wrsim.load_library([ROOT / "vhdl" / "ieee", path]), top)


def simulate(tmp_path: Path, d, stop: float = 1.0):
    return wrsim.simulate(d, wrsim.Analysis(stop=stop, max_step=1e-3), tmp_path / "work", title="test")


def test_explicit_quantities_leave_the_netlist_and_keep_their_values(tmp_path):
    d = design(tmp_path, DECAY, "tb")
    small = eliminated(d)
    assert sorted(small.top.eliminated) == ["w", "y", "z"]
    assert list(small.top.unknowns) == ["x"]
    assert d.top.unknowns.keys() == {"x", "y", "w", "z"}  # the elaborated IR stays whole
    netlist = wrsim.lower(d, wrsim.Analysis(stop=1.0, compiled=False), "test").text  # the behavioural sources
    assert "b_y__eq" not in netlist and "b_w__eq" not in netlist and "b_x__eq" in netlist
    assert "* w = ((3 * v(x)) + 1): explicit, substituted where it is read (no node)" in netlist
    w = simulate(tmp_path, d)
    x = np.exp(-w.time / 0.2)
    np.testing.assert_allclose(w["x"], x, rtol=2e-3, atol=1e-6)
    np.testing.assert_allclose(w["y"], 3.0 * w["x"] + 1.0, rtol=1e-12)
    np.testing.assert_allclose(w["w"], w["y"], rtol=1e-12)
    np.testing.assert_allclose(w["z"], w["x"] ** 2, rtol=1e-12)
    assert w.unit("z") == "1"


def test_a_mapped_generic_reaches_the_probe_of_an_eliminated_quantity(tmp_path):
    d = design(tmp_path, CHILD, "tb2")
    assert "inner" in eliminated(d).models[0].eliminated
    w = simulate(tmp_path, d, stop=0.5)
    np.testing.assert_allclose(w["c1.inner"], 5.0 * (2.0 + w.time), rtol=1e-9)
    np.testing.assert_allclose(w["q"], 2.0 + w.time, rtol=1e-9)


def test_a_save_list_saves_what_an_eliminated_quantity_is_made_of(tmp_path):
    d = design(tmp_path, DECAY, "tb")
    net = wrsim.lower(d, wrsim.Analysis(stop=1.0, save=("w",)), "test")
    assert ".save v(x)" in net.text.splitlines()


def test_what_stays_an_unknown(tmp_path):
    big = " + ".join(f"sin({k}.0 * x)" for k in range(1, 5))  # more than SMALL sub-expressions
    text = f"""
entity tb3 is
end entity tb3;
architecture s of tb3 is
  quantity x : real;   -- [1] state
  quantity b : real;   -- [1] large, read twice
  quantity c : real;   -- [1] reads b
  quantity e : real;   -- [1] reads b
  quantity l1 : real;  -- [1] algebraic loop with l2
  quantity l2 : real;  -- [1]
  quantity k : real;   -- [1] a constant
begin
  if domain = quiescent_domain use
    x == 0.0;
  else
    x'dot == 1.0;
  end use;
  b == {big};
  c == b * 2.0;
  e == b * 3.0;
  l1 == 0.5 * l2 + 1.0;
  l2 == 0.5 * l1;
  k == 4.0;
end architecture s;
"""
    d = design(tmp_path, text, "tb3")
    small = eliminated(d)
    assert sum(1 for _ in sy.walk(next(eq.residual for eq in d.top.equations if eq.paired == "b"))) > SMALL
    assert {"x", "b", "k"} <= set(small.top.unknowns)  # a 'dot's node, large and shared, a constant
    assert {"c", "e"} <= set(small.top.eliminated)
    assert {"l1", "l2"} & set(small.top.unknowns)  # an algebraic loop keeps an unknown
    assert small.unknowns() == (len(small.top.unknowns), len(small.top.eliminated))
    w = simulate(tmp_path, d, stop=0.1)
    np.testing.assert_allclose(w["l1"], 4.0 / 3.0, rtol=1e-6)  # l1 = 0.25*l1 + 1
    np.testing.assert_allclose(w["l2"], 2.0 / 3.0, rtol=1e-6)
    np.testing.assert_allclose(w["e"], 1.5 * w["c"], rtol=1e-9)
    t = 0.05
    k = int(np.searchsorted(w.time, t))
    assert w["b"][k] == pytest.approx(sum(math.sin(j * w["x"][k]) for j in range(1, 5)), rel=1e-4)  # reltol


def test_dump_model_reports_the_bench_unknowns():
    d = wrsim.elaborate(wrsim.load_library(), "tb_motor_characteristic", wrsim.load_params("fpg2_12nm"))
    text = eliminated(d).describe()
    unknowns, gone = eliminated(d).unknowns()
    assert text.splitlines()[0].startswith(f"{unknowns} unknowns over all instances, {gone} quantities eliminated")
    assert "  eliminated speed_rpm = " in text
    assert gone >= 2 and unknowns + gone == d.unknowns()[0]
