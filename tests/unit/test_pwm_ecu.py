"""The semiconductor ECU (vhdl/electronics/h_bridge.vhd, ecu_sense.vhd, vhdl/digital/motor_controller.vhd): each mode
of the averaged H-bridge against its closed form, the ADC codes, the ECU concept of a scenario, and the bridge's
inputs reported at the end of the analog step (wrsim_lazy)."""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from conftest import netlist
from wrsim.benches.scenario import ECUS, load_scenario, scenario_params, scenario_run
from wrsim.errors import WrsimError

FILES = ("vhdl/electronics", "vhdl/digital", "vhdl/equipment", "vhdl/drive", "tests/fixtures/pwm")
R_ON, V_F, R_F, T_D = 5.0e-3, 0.8, 5.0e-3, 5.0e-7 * 2.0e4  # h_bridge defaults (wr_params), dead time x f_pwm
DUTY = 614 / 1023


def at(w, name: str, t: float) -> float:
    return float(w[name][np.searchsorted(w.time, t)])


@pytest.fixture(scope="module")
def modes(tmp_path_factory):
    from wrsim import NgspiceBatch

    net = netlist("tb_bridge_modes", 1.0, 1e-4, FILES)
    folder, runner = tmp_path_factory.mktemp("modes"), NgspiceBatch()
    runner.build(net, folder)
    return runner.run(net, folder)


def test_drive_on_a_resistor_is_the_averaged_leg_in_closed_form(modes):
    # leg A switches: high side a_h of the period, low side a_l, its low body diode the dead time a_d (i > 0);
    # leg B's low side carries the current back: u = a_h*U - a_d*v_f - i*(a_h*R + a_l*R + a_d*r_f + R)
    a_h, a_l = DUTY - T_D, 1.0 - DUTY - T_D
    a_d = 1.0 - a_h - a_l
    i = (a_h * 13.0 - a_d * V_F) / (1.0 + R_ON * (a_h + a_l + 1.0) + a_d * R_F)
    assert at(modes, "i_load", 0.29) == pytest.approx(i, rel=1e-6)
    # the battery gives what the high side carries
    assert at(modes, "resistive.i_bat", 0.29) == pytest.approx(a_h * i, rel=1e-6)


def test_brake_shorts_the_motor_through_both_low_sides(modes):
    for t in (0.301, 0.35, 0.45):
        assert at(modes, "hb.u_m", t) == pytest.approx(-2 * R_ON * at(modes, "hb.i_m", t), abs=1e-9)
        assert at(modes, "hb.i_bat", t) == pytest.approx(0.0, abs=1e-9)
    assert at(modes, "hb.i_m", 0.301) < -3.0  # the turning armature's back-EMF drives the braking current
    assert abs(at(modes, "motor.omega", 0.49)) < 1.0


def test_off_returns_the_current_through_two_body_diodes_and_then_blocks(modes):
    # from 0.8 s all four MOSFETs are off: the load's current of the run down (i < 0) decays through the high diode
    # of leg A and the low diode of leg B into the battery, u = U + 2*v_f - 2*r_f*i, then the diodes block
    t = modes.time
    assert at(modes, "resistive.i_m", 0.79) < -5.0
    flowing = (t > 0.80001) & (modes["resistive.i_m"] < -0.1)  # the mode reaches the bridge 1 us after 0.8 s
    assert np.count_nonzero(flowing) >= 3
    u, i = modes["resistive.u_m"][flowing], modes["resistive.i_m"][flowing]
    assert np.allclose(u, 13.0 + 2 * V_F - 2 * R_F * i, atol=1e-6)
    assert np.allclose(modes["resistive.i_bat"][flowing], i, atol=1e-9)
    assert abs(at(modes, "resistive.i_m", 0.9)) < 1e-3  # blocked
    assert abs(at(modes, "hb.i_m", 0.99)) < 0.05 and abs(at(modes, "motor.omega", 0.99)) > 50.0  # the motor coasts


def test_the_adc_codes_are_the_quantized_current_and_supply(modes):
    t = modes.time
    for when in (0.2, 0.4, 0.6):
        k = np.searchsorted(t, when)
        i = modes["sense.i"][k]
        assert modes["current_code"][k] == math.floor((2.5 + 100 * 1e-3 * i) / 5.0 * 1024)
    assert modes["supply_code"][np.searchsorted(t, 0.5)] == 130


def test_the_motor_controllers_bridge_inputs_are_reported_at_the_end_of_the_step():
    from wrsim import Analysis, elaborate, load_library, lower

    design = elaborate(load_library(), "tb_closed_loop", scenario_params(), {"ecu_kind": 1})
    net = lower(design, Analysis(stop=1.0, max_step=1e-3, compiled=False), "tb_closed_loop")
    (control,) = [d for d in net.digital if d.entity == "motor_controller"]
    assert {"duty", "mode", "dir", "effort"} <= set(control.lazy)
    (ecu,) = [d for d in net.digital if d.entity == "ecu_software"]
    assert "relay_up" in ecu.lazy  # the motor controller reads it, no analog element


SCENARIO = """\
purpose = "a closing with the PWM ECU"
params = ["antipinch/observer_rise"]
ecu = "pwm"
stop = 4.0

[switch]
sequence = "compliance"
"""


def test_a_scenario_chooses_the_ecu(tmp_path: Path):
    path = tmp_path / "case.toml"
    path.write_text(SCENARIO, encoding="utf-8")
    run = scenario_run(load_scenario(path), scenario_params())
    assert run.generics["ecu_kind"] == 1
    assert isinstance(run.params, tuple) and run.params[0] == ECUS["pwm"][1]
    path.write_text(SCENARIO.replace('ecu = "pwm"\n', ""), encoding="utf-8")
    assert "ecu_kind" not in scenario_run(load_scenario(path), scenario_params()).generics  # the thesis's relays


@pytest.mark.parametrize("value", ['"mosfet"', "1"])
def test_an_unknown_ecu_is_one_error_at_its_line(tmp_path: Path, value: str):
    path = tmp_path / "case.toml"
    path.write_text(SCENARIO.replace('"pwm"', value), encoding="utf-8")
    with pytest.raises(WrsimError, match=r"case.toml:3: ecu: 'relay' or 'pwm'"):
        load_scenario(path)


@pytest.mark.parametrize(
    "line, message",
    [
        ("close_mm_s = -5 mm/s", "close_mm_s = -5: must be > 0"),
        ("ramp_mm_s2 = 0 mm/s**2", "ramp_mm_s2 = 0: must be > 0"),
        ("pinch_mm_s = 200 mm/s", "pinch_mm_s = 200: must not exceed the closing speed close_mm_s = 125 mm/s"),
        ("start_mm_s = 130 mm/s", "start_mm_s = 130: must not exceed the closing speed close_mm_s = 125 mm/s"),
        ("close_mm_s = 900 mm/s", "close_mm_s = 900: the drive does not reach it at 13 V: 28512 rpm"),
    ],
)
def test_a_bad_profile_is_one_error_naming_the_key_before_anything_runs(tmp_path: Path, capsys, line, message):
    from wrsim import cli

    bad = tmp_path / "profile.txt"
    bad.write_text(f"[motor_controller]\n{line}  # a mistake\n", encoding="utf-8")
    case = tmp_path / "case.toml"
    case.write_text(SCENARIO.replace('"antipinch/observer_rise"', f'"antipinch/observer_rise", "{bad}"'))
    results = tmp_path / "results"
    assert cli.main(["scenario", str(case), "--results", str(results)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{bad}:2: [motor_controller] {message}" in err
    assert not results.exists()


def test_the_bridges_on_resistance_follows_the_ambient_temperature():
    from wrsim.data.params import Param, ParamSet
    from wrsim.data.temperature import at_temperature

    pwm = scenario_params(["ecu/pwm"])
    for celsius, factor in ((20.0, 1.0), (85.0, 1.325), (-40.0, 0.7)):
        hot = pwm.overlay(ParamSet("t", None, {"ambient": {"temperature": Param(celsius, "degC", "t", 1)}}))
        assert at_temperature(hot).number_in("h_bridge", "r_ds_on", "Ohm") == pytest.approx(5e-3 * factor)


def test_a_bad_profile_stops_the_pwm_bench_before_it_runs(tmp_path: Path, capsys):
    from wrsim import cli

    bad = tmp_path / "profile.txt"
    bad.write_text("[motor_controller]\nstop_mm_s = 0 mm/s  # a mistake\n", encoding="utf-8")
    results = tmp_path / "results"
    args = ["testbench", "--bench", "compliance-pwm", "--params", str(bad), "--results", str(results)]
    assert cli.main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{bad}:2: [motor_controller] stop_mm_s = 0: must be > 0" in err
    assert not results.exists()


@pytest.mark.skipif(shutil.which("ghdl-llvm") is None, reason="GHDL not installed (make setup installs it)")
def test_a_run_from_rest_starts_soft_whenever_it_is_asked_for(tmp_path: Path):
    """motor_controller asked for a run up 1 s after power-up (tests/fixtures/pwm/tb_controller_start.vhd): the set
    speed ramps from 0 at the request, so the duty at the request, 5 ms and 10 ms later is the PI law's on the ramp
    (wr_digital_params' defaults, 13.0 V, the motor at rest) -- not the full set speed with an integral wound up over
    the second the controller was idle."""
    from test_ecu_vhdl import DIGITAL_FILES, ghdl_run

    from wrsim.paths import ROOT

    files = [*DIGITAL_FILES(["motor_controller"]), ROOT / "tests" / "fixtures" / "pwm" / "tb_controller_start.vhd"]
    out = ghdl_run(tmp_path, files, "tb_controller_start")
    assert out.returncode == 0, out.stdout + out.stderr
    kp, ki, rpm_per_volt, ramp = 900e-6, 0.04, 480.0, 2000.0 * 2112 * 60 / 4 / 1000  # [V/rpm], ..., [rpm/s]
    expected, x_int = [], 0.0
    for k in range(3):
        n_ref = ramp * 0.005 * k  # the motor at rest: the error is the set speed
        expected.append(round((n_ref / rpm_per_volt + kp * n_ref + x_int) / 13.0 * 1023))
        x_int += ki * n_ref * 0.005
    reported = [int(ln.rsplit(":", 1)[1]) for ln in out.stdout.splitlines() if "duty at " in ln]
    assert expected == [0, 74, 154]
    assert reported == expected


@pytest.mark.skipif(shutil.which("ghdl-llvm") is None, reason="GHDL not installed (make setup installs it)")
def test_the_start_phase_caps_the_set_speed_for_its_time(tmp_path: Path):
    """With start_mm_s = 8 mm/s for start_ms = 20 ms (tb_controller_start), the set speed ramps from 0 to the cap
    (253.44 rpm, reached before the 5 ms task: a ramp step is 316.8 rpm), holds it at 10 and 15 ms, and ramps on from
    20 ms, the phase over; the duties are the PI law's on that set speed with the motor at rest."""
    from test_ecu_vhdl import DIGITAL_FILES, ghdl_run

    from wrsim.paths import ROOT

    files = [*DIGITAL_FILES(["motor_controller"]), ROOT / "tests" / "fixtures" / "pwm" / "tb_controller_start.vhd"]
    out = ghdl_run(tmp_path, files, "tb_controller_start", "start_mm_s=8", "start_ms=20", "tasks=6")
    assert out.returncode == 0, out.stdout + out.stderr
    kp, ki, rpm_per_volt, per_mm_s = 900e-6, 0.04, 480.0, 2112 * 60 / 4 / 1000  # [V/rpm], ..., [rpm per mm/s]
    step, cap = 2000.0 * 0.005 * per_mm_s, 8 * per_mm_s
    n_refs = [0.0, cap, cap, cap, cap + step, cap + 2 * step]
    expected, x_int = [], 0.0
    for n_ref in n_refs:
        expected.append(round((n_ref / rpm_per_volt + kp * n_ref + x_int) / 13.0 * 1023))
        x_int += ki * n_ref * 0.005
    reported = [int(ln.rsplit(":", 1)[1]) for ln in out.stdout.splitlines() if "duty at " in ln]
    assert reported == expected
