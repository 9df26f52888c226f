"""Mixed-signal lowering: A->D signal assignments (adc_bridge), D->A use of signal ports (dac_bridge), vector
signals decoded with to_integer(unsigned(...)), and bench signals recorded as waveforms."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import netlist
from wrsim import paths
from wrsim.elab import elaborate
from wrsim.elab.library import load_library
from wrsim.errors import SourceError
from wrsim.frontend import ast
from wrsim.frontend.parser import parse_text

FILES = ("tests/fixtures/signals",)


def at(w, name, t):
    return w[name][np.searchsorted(w.time, t)]


def test_comparator_drives_a_switched_source(simulate):
    w = simulate("tb_sig", 1.0, max_step=1e-3, files=FILES)
    # va = 3 V/s * t crosses the 1.5 V threshold at 0.5 s and 2 V at 2/3 s
    assert at(w, "s", 0.49) == 0 and at(w, "s", 0.51) == 1
    assert at(w, "c", 0.49) == 2 and at(w, "c", 0.6) == 3 and at(w, "c", 0.7) == 1
    assert at(w, "src.v", 0.45) == pytest.approx(1.0)  # off
    assert at(w, "src.v", 0.6) == pytest.approx(8.0)  # on, 5 + code 3
    assert at(w, "src.v", 0.8) == pytest.approx(6.0)  # on, 5 + code 1
    edge = w.time[np.argmax(w["s"] > 0.5)]
    assert 0.0 <= edge - 0.5 <= 1e-6  # a time point at the crossing (test_crossings)


def test_netlist_uses_bridges_and_keeps_names():
    text = netlist("tb_sig", 1.0, 1e-3, files=FILES).text
    assert ".subckt t_comparator p q code_0 code_1 params: threshold=0.5" in text
    assert "a_q__adc [q__lvl] [q] wrsim_adc" in text
    assert "a_on_cmd__dac [on_cmd] [on_cmd__a] wrsim_dac" in text
    assert "x_cmp a s c_0 c_1 t_comparator threshold=1.5" in text


@pytest.mark.parametrize("stmt", ["q <= v'above(1.0);", "q <= '1' when v'above(1.0) else 'Z';"])
def test_an_output_port_takes_only_the_a_to_d_form(tmp_path, stmt):
    """Any other concurrent assignment is the equivalent process (IEEE 1076 11.6), and a process drives the
    signals its architecture declares, not a signal port: one error at the assignment naming the A->D form."""
    path = tmp_path / "m.vhd"
    path.write_text(
        "library ieee;\nuse ieee.std_logic_1164.all;\nentity e is\n  port (signal q : out std_logic);\n"
        "end entity e;\narchitecture a of e is\n  quantity v : real;\nbegin\n  v == 2.0;\n  "
        + stmt
        + "\nend architecture a;\nlibrary ieee;\nuse ieee.std_logic_1164.all;\nentity tb is\nend entity tb;\n"
        "architecture t of tb is\n  signal q : std_logic;\nbegin\n  dut: entity work.e port map (q => q);\n"
        "end architecture t;\n"
    )
    with pytest.raises(
        SourceError, match=r"m\.vhd:10:3: 'q' is a signal port: the analog side drives it with the A->D form"
    ):
        elaborate(load_library([paths.VHDL / "ieee", path]), "tb")


def test_a_conditional_assignment_is_its_equivalent_process():
    text = "architecture a of e is\nbegin\n  s <= 1.0 when t = '1' else 2.0 after 1 ms;\nend architecture a;\n"
    (arch,) = parse_text(text, "m.vhd").units
    (proc,) = arch.stmts
    assert isinstance(proc, ast.Process) and proc.implied
    assert [x.ident for x in proc.sensitivity] == ["t"]  # the names it reads; elaboration keeps the signals
    (branches,) = [s.branches for s in proc.body]
    assert [type(c).__name__ for c, _ in branches] == ["Binary", "NoneType"]
    assert branches[1][1][0].after is not None


def test_a_file_without_ams_is_left_to_ghdl():
    text = (
        "library ieee;\nuse ieee.std_logic_1164.all;\nentity counter is\n  generic (n : natural := 4);\n"
        "  port (clk : in std_logic; count : out integer);\nend entity counter;\n"
        "architecture rtl of counter is\n  signal c : integer := 0;\nbegin\n"
        "  process (clk) begin if rising_edge(clk) then c <= c + 1; end if; end process;\n"
        "  count <= c;\nend architecture rtl;\n"
    )
    df = parse_text(text, "counter.vhd")
    assert df.digital
    ent, arch = df.units
    assert [(p.name, p.mode, p.width) for p in ent.ports] == [("clk", "in", None), ("count", "out", 32)]
    assert type(arch).__name__ == "DigitalArchitecture" and arch.entity == "counter"


def test_ghdl_unit_in_the_loop(simulate):
    """A digital unit run by GHDL (d_cosim) counts comparator edges from the ngspice plant and switches it."""
    w = simulate("tb_counted", 0.5, max_step=1e-4, files=FILES, overrides={"max_edges": 3})
    # sin(2*pi*10*t) rises through 0.5 at t = (1/12 + k) / 10 s
    edges = [(1 / 12 + k) / 10 for k in range(5)]
    assert at(w, "count", edges[0] - 1e-3) == 0 and at(w, "count", edges[0] + 1e-3) == 1
    assert at(w, "count", edges[2] + 1e-3) == 3 and at(w, "count", 0.49) == 5
    switch_on = w.time[np.argmax(w["done"] > 0.5)]
    assert switch_on == pytest.approx(edges[2], abs=3e-4)  # input latency is bounded by max_step
    assert at(w, "src.v", edges[2] - 2e-3) == pytest.approx(1.0) and at(w, "src.v", 0.45) > 5.0


def test_bad_generic_of_a_digital_unit_is_reported_before_ngspice(simulate):
    from wrsim.errors import WrsimError

    with pytest.raises(WrsimError, match="max_edges must be <= 15"):
        simulate("tb_counted", 0.1, max_step=1e-4, files=FILES, overrides={"max_edges": 20})


def test_digital_files_come_in_dependency_order(tmp_path):
    from wrsim.elab.library import load_library

    unit = (
        "library ieee;\nuse ieee.std_logic_1164.all;\nentity z_unit is\n  port (a : in std_logic; b : out "
        "std_logic);\n"
        "end entity z_unit;\narchitecture rtl of z_unit is\nbegin\n  p: process (a) begin b <= a; end process p;\n"
        "end architecture rtl;\n"
    )
    user = (
        "library ieee;\nuse ieee.std_logic_1164.all;\nentity a_user is\n  port (x : in std_logic; y : out "
        "std_logic);\n"
        "end entity a_user;\narchitecture rtl of a_user is\n  type t is (one, two);\nbegin\n"
        "  u: entity work.z_unit port map (a => x, b => y);\nend architecture rtl;\n"
    )
    unrelated = unit.replace("z_unit", "m_other")
    for name, text in (("z_unit.vhd", unit), ("a_user.vhd", user), ("m_other.vhd", unrelated)):
        (tmp_path / name).write_text(text, encoding="utf-8")
    lib = load_library([tmp_path])
    assert [p.name for p in lib.digital_files(["a_user"])] == ["z_unit.vhd", "a_user.vhd"]
    assert [p.name for p in lib.digital_files(["m_other"])] == ["m_other.vhd"]
