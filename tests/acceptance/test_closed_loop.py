"""The closed-loop window-regulator system (issue 5): ECU software and switch in GHDL, the plant in ngspice
(testbenches/tb_closed_loop.vhd). The normalization/pinch benches are not registered yet (see issue 5)."""
from __future__ import annotations


def test_closed_loop_bench_lowers_with_the_digital_units(lib):
    from wrsim.benches import ROOT
    from wrsim.elaborate import elaborate
    from wrsim.ngspice import Analysis, lower
    from wrsim.params import load_params

    seq = str(ROOT / "params" / "sequences" / "pinch.txt")
    design = elaborate(lib, "tb_closed_loop", load_params(ROOT / "params" / "rail_wr_8p5nm.txt"),
                       {"sequence_file": seq, "pinch_position": 0.36, "gauge_travel": 0.2, "gauge_insert": 10.0})
    net = lower(design, Analysis(1.0, 5e-5), "closed loop")
    units = {u.entity: u for u in net.digital}
    assert set(units) == {"ecu_software", "switch"}
    assert units["switch"].generics["sequence_file"] == seq
    widths = {p.name: p.width or 1 for p in units["ecu_software"].ports}
    assert widths["position"] == 32 and widths["supply_code"] == 8 and widths["hall_a"] == 1
    assert {"supply.ua", "pinch_force", "door.pane.pos", "position", "normalized", "pinch"} <= set(net.probes)
