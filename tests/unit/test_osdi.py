"""The compiled models (wrsim.backend.ngspice.osdi): each architecture's equations as an OSDI device.

The device code is checked through its own descriptor (loaded with ctypes, as ngspice's loader reads it):
residuals and Jacobian entries against the closed form of a nonlinear junction with a 'dot in its reactive part,
with a generic per instance. Whole runs are checked against closed forms and against the behavioural netlist;
the corpus runs compiled in tests/unit/test_corpus.py."""

from __future__ import annotations

import ctypes as C
import dataclasses
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

from conftest import ANALYTIC, _library
from wrsim import paths
from wrsim.backend.ngspice import osdi
from wrsim.backend.ngspice.batch import NgspiceBatch
from wrsim.backend.ngspice.netlist import RAW_FILE, Analysis, compiled_setting, lower
from wrsim.backend.ngspice.raw import read_raw
from wrsim.cli import main
from wrsim.data.params import load_params
from wrsim.elab import elaborate
from wrsim.elab import symbolic as sy
from wrsim.elab.design import generic_values
from wrsim.errors import WrsimError

_U32, _PTR, _NONE = C.c_uint32, C.c_void_p, 0xFFFFFFFF


class _Node(C.Structure):
    _fields_ = [
        ("name", C.c_char_p),
        ("units", C.c_char_p),
        ("residual_units", C.c_char_p),
        ("resist_off", _U32),
        ("react_off", _U32),
        ("lim1", _U32),
        ("lim2", _U32),
        ("flow", C.c_bool),
    ]


class _Entry(C.Structure):
    _fields_ = [("row", _U32), ("col", _U32), ("react_ptr_off", _U32), ("flags", _U32)]


class _Info(C.Structure):
    _fields_ = [
        ("paras", _PTR * 4),
        ("abstime", C.c_double),
        ("prev_solve", C.POINTER(C.c_double)),
        ("prev_state", _PTR),
        ("next_state", _PTR),
        ("flags", _U32),
    ]


class _InitInfo(C.Structure):
    _fields_ = [("flags", _U32), ("num_errors", _U32), ("errors", _PTR)]


_LOAD = C.CFUNCTYPE(None, _PTR, _PTR, C.c_double)


class _Descriptor(C.Structure):
    _fields_ = [
        ("name", C.c_char_p),
        ("num_nodes", _U32),
        ("num_terminals", _U32),
        ("nodes", C.POINTER(_Node)),
        ("num_entries", _U32),
        ("entries", C.POINTER(_Entry)),
        ("num_collapsible", _U32),
        ("collapsible", _PTR),
        ("collapsed_offset", _U32),
        ("noise_sources", _PTR),
        ("num_noise", _U32),
        ("num_params", _U32),
        ("num_instance_params", _U32),
        ("num_opvars", _U32),
        ("params", _PTR),
        ("node_mapping_offset", _U32),
        ("jacobian_ptr_resist_offset", _U32),
        ("num_states", _U32),
        ("state_idx_off", _U32),
        ("bound_step_offset", _U32),
        ("instance_size", _U32),
        ("model_size", _U32),
        ("access", C.CFUNCTYPE(_PTR, _PTR, _PTR, _U32, _U32)),
        ("setup_model", _PTR),
        ("setup_instance", C.CFUNCTYPE(None, _PTR, _PTR, _PTR, C.c_double, _U32, _PTR, _PTR)),
        ("eval", C.CFUNCTYPE(_U32, _PTR, _PTR, _PTR, _PTR)),
        ("load_noise", _PTR),
        ("load_residual_resist", _PTR),
        ("load_residual_react", _PTR),
        ("load_limit_rhs_resist", _PTR),
        ("load_limit_rhs_react", _PTR),
        ("load_spice_rhs_dc", _PTR),
        ("load_spice_rhs_tran", _PTR),
        ("load_jacobian_resist", C.CFUNCTYPE(None, _PTR, _PTR)),
        ("load_jacobian_react", _LOAD),
        ("load_jacobian_tran", _LOAD),
    ]


@dataclasses.dataclass
class _Eval:
    F: np.ndarray  # resistive residual per node
    Q: np.ndarray  # reactive residual (charge) per node
    JF: np.ndarray  # dF/dx, dense
    JQ: np.ndarray  # dQ/dx, dense


class _Device:
    """One descriptor of a compiled library, evaluated the way ngspice's loader calls it."""

    def __init__(self, lib: Path, name: str):
        self.lib = C.CDLL(str(lib))
        assert _U32.in_dll(self.lib, "OSDI_VERSION_MAJOR").value == 0
        assert _U32.in_dll(self.lib, "OSDI_VERSION_MINOR").value == 3
        count = _U32.in_dll(self.lib, "OSDI_NUM_DESCRIPTORS").value
        found = [d for d in (_Descriptor * count).in_dll(self.lib, "OSDI_DESCRIPTORS") if d.name.decode() == name]
        assert found, f"no descriptor {name}"
        self.d = found[0]
        self.nodes = [self.d.nodes[k].name.decode() for k in range(self.d.num_nodes)]

    def instance(self, params: dict[int, float]) -> C.Array:
        """A set-up instance with these parameters (0 is $mfactor), its node k on equation k + 1."""
        d, n = self.d, self.d.num_nodes
        inst = (C.c_char * d.instance_size)()
        base = C.addressof(inst)
        mapping = (_U32 * n).from_address(base + d.node_mapping_offset)
        for k in range(n):
            mapping[k] = k + 1  # equation 0 is ground
        for pid, value in params.items():
            C.c_double.from_address(d.access(base, None, pid, 1 | 4)).value = value
        d.setup_instance(None, base, None, 300.0, n, None, C.addressof(_InitInfo()))
        return inst

    def eval(self, inst: C.Array, x: dict[str, float], t: float = 1.0) -> int:
        """One evaluation of `inst` at the solution `x` and time `t`: its flags (1: another iteration asked for)."""
        solution = (C.c_double * (self.d.num_nodes + 1))(0.0, *[x[name] for name in self.nodes])
        info = _Info(abstime=t, prev_solve=solution)  # alive for the call
        return int(self.d.eval(None, C.addressof(inst), None, C.addressof(info)))

    def __call__(self, x: dict[str, float], params: dict[int, float], t: float = 1.0) -> _Eval:
        d, n = self.d, self.d.num_nodes
        inst = self.instance(params)
        base = C.addressof(inst)
        self.eval(inst, x, t)
        F = np.array([C.c_double.from_address(base + d.nodes[k].resist_off).value for k in range(n)])
        Q = np.array(
            [
                C.c_double.from_address(base + d.nodes[k].react_off).value if d.nodes[k].react_off != _NONE else 0.0
                for k in range(n)
            ]
        )
        jf, jq = (C.c_double * d.num_entries)(), (C.c_double * d.num_entries)()
        resist = (_PTR * d.num_entries).from_address(base + d.jacobian_ptr_resist_offset)
        for k in range(d.num_entries):
            resist[k] = C.addressof(jf) + 8 * k
            if d.entries[k].react_ptr_off != _NONE:
                _PTR.from_address(base + d.entries[k].react_ptr_off).value = C.addressof(jq) + 8 * k
        d.load_jacobian_resist(base, None)
        d.load_jacobian_react(base, None, 1.0)
        JF, JQ = np.zeros((n, n)), np.zeros((n, n))
        for k in range(d.num_entries):
            JF[d.entries[k].row, d.entries[k].col] += jf[k]
            JQ[d.entries[k].row, d.entries[k].col] += jq[k]
        return _Eval(F, Q, JF, JQ)


def _design(entity: str = "t_diode_cap_tb"):
    return elaborate(_library((ANALYTIC,)), entity, None, None)


@pytest.fixture(scope="module")
def junctions(tmp_path_factory: pytest.TempPathFactory) -> tuple[_Device, osdi.Device]:
    design = _design()
    dev = osdi.device(design.top, generic_values(design.top))
    assert dev is not None
    lib = osdi.build(osdi.library(dev), tmp_path_factory.mktemp("osdi"))
    return _Device(lib, dev.name), dev


def test_junction_residuals_and_jacobian_match_the_closed_form(junctions):
    """Both junctions of the bench in the one netlist-wide device, each with its own generics (instance
    parameters, changed here from the bench's values): the equation's row holds i - law (or its negative), the
    terminal the through current, the 'dot node its own value (F) against the across quantity (Q = -v)."""
    device, dev = junctions
    assert dev.params == {
        "p_d1_c0": 1e-6,
        "p_d1_is0": 1e-9,
        "p_d1_vt": 0.05,
        "p_d2_c0": 3e-6,
        "p_d2_is0": 2e-8,
        "p_d2_vt": 0.08,
    }
    generics = {"d1": (3e-9, 0.06, 2e-6), "d2": (5e-8, 0.09, 4e-6)}  # is0, vt, c0
    ids = {name: k for k, name in enumerate(dev.params, start=1)}  # 0 is $mfactor
    params = {ids[f"p_{d}_{g}"]: v for d, vals in generics.items() for g, v in zip(("is0", "vt", "c0"), vals)}
    node = {n: k for k, n in enumerate(device.nodes)}
    rng = np.random.default_rng(7)
    for _ in range(20):
        x = {n: rng.normal(0.0, 50.0 if n.endswith("__dot") else 0.2 if "." not in n else 1e-3) for n in device.nodes}
        e = device(x, params)
        for d, terminal in (("d1", "a"), ("d2", "b")):
            is0, vt, c0 = generics[d]
            i, dot, v = x[f"x_{d}.i"], x[f"x_{d}.v__dot"], x[terminal]
            law = is0 * (np.exp(v / vt) - 1.0) + c0 * dot
            row = e.F[node[f"x_{d}.i"]]
            assert abs(abs(row) - abs(i - law)) <= 1e-12 * (1 + abs(law))
            sign = 1.0 if row * (i - law) >= 0 else -1.0
            assert e.F[node[f"x_{d}.v__dot"]] == dot and e.Q[node[f"x_{d}.v__dot"]] == pytest.approx(-v, abs=1e-15)
            jac = e.JF[node[f"x_{d}.i"]]
            slope = is0 / vt * np.exp(v / vt)
            assert [jac[node[f"x_{d}.i"]], jac[node[terminal]], jac[node[f"x_{d}.v__dot"]]] == pytest.approx(
                [sign, -sign * slope, -sign * c0], rel=1e-12
            )
            assert e.JQ[node[f"x_{d}.v__dot"], node[terminal]] == -1.0
        # the terminal a carries the current of d1 (leaving) and of the resistor ra (entering)
        assert e.F[node["a"]] == pytest.approx(x["x_d1.i"] - x["ira"], rel=1e-15, abs=1e-300)
        # and the Jacobian is the derivative of the residual (central differences)
        for k, name in enumerate(device.nodes):
            h = 1e-6 * max(1.0, abs(x[name]))
            up, down = device({**x, name: x[name] + h}, params), device({**x, name: x[name] - h}, params)
            assert (up.F - down.F) / (2 * h) == pytest.approx(e.JF[:, k], rel=1e-5, abs=1e-9)


def _compiled(design, tmp_path: Path) -> tuple[_Device, C.Array]:
    """The compiled device of `design` and an instance with its generics as the instance line gives them."""
    dev = osdi.device(design.top, generic_values(design.top))
    assert dev is not None
    device = _Device(osdi.build(osdi.library(dev), tmp_path), dev.name)
    return device, device.instance(dict(enumerate(dev.params.values(), start=1)))


def test_an_equation_not_yet_met_asks_for_another_iteration(tmp_path: Path):
    """In place of the behavioural sources' convergence test: while an equation's residual exceeds abstol at a
    load, the device asks for another Newton iteration, at most WRSIM_FLAGS = 3 times at one time point; a new
    time point starts over. The friction force f = f_c * smooth_sign(v, v_th), f_c = 3 N, v_th = 1 mm/s."""
    design = _design("t_coulomb_stop")
    device, inst = _compiled(design, tmp_path)  # as the instance line gives them
    base = {n: 0.0 for n in device.nodes}

    def at(v: float, f: float, t: float = 1.0) -> int:  # the slider's speed, a friction force, the time
        return device.eval(inst, {**base, "slider": v, "x_friction.f": f}, t)

    assert at(5e-4, 1.5) == 0  # met: 3 N * 0.5
    assert at(5e-4, 1.5 + 1e-13) == 0  # within abstol (1e-12 before ngspice sets it)
    assert at(3e-3, 1.5) == 1  # not met: the force saturates at 3 N
    assert [at(3e-3, 1.5) for _ in range(3)] == [1, 1, 0]  # three asks in all at this time point
    assert at(3e-3, 1.5, t=2.0) == 1  # a new time point: asked afresh
    assert at(3e-3, 3.0, t=2.0) == 0


def test_an_iterate_that_cycles_over_a_friction_band_is_put_just_inside_it(tmp_path: Path):
    """Newton limiting (ngspice.limiting): the slider's speed iterates -3, +3, -3 mm/s at one time point skip the
    friction band |v| < v_th = 1 mm/s both ways; the third is evaluated just inside the band, 1e-3 of its width below
    its upper edge (f_c * smooth_sign = 3 N * 0.998 there), and the device asks for another iteration. A new time
    point, or iterates that do not turn back, are left as they are."""
    design = _design("t_coulomb_stop")
    device, inst = _compiled(design, tmp_path)
    row = device.d.nodes[device.nodes.index("x_friction.f")].resist_off
    base = {n: 0.0 for n in device.nodes}

    def friction(v: float, t: float = 1.0) -> tuple[float, int]:  # the force law evaluated, the flags
        flags = device.eval(inst, {**base, "slider": v, "x_friction.f": 0.0}, t)
        return abs(C.c_double.from_address(C.addressof(inst) + row).value), flags

    assert friction(-3e-3)[0] == pytest.approx(3.0)
    assert friction(3e-3)[0] == pytest.approx(3.0)
    force, flags = friction(-3e-3)  # back across the band: limited to 1e-3 - 1e-3 * 2e-3
    assert force == pytest.approx(3.0 * 0.998, rel=1e-9) and flags & 1
    assert friction(-3e-3, t=2.0) == (pytest.approx(3.0), 1)  # a new time point: no history (asks: the residual)
    assert friction(-2e-3, t=2.0)[0] == pytest.approx(3.0)  # the same side: nothing to limit


def test_a_run_with_compiled_models_follows_the_closed_form_and_the_behavioural_netlist(tmp_path: Path):
    waves = {}
    for compiled in (False, True):
        net = lower(_design("t_rc_step"), Analysis(stop=5e-3, max_step=5e-6, compiled=compiled), "t_rc_step")
        assert ("pre_osdi" in net.text) == compiled and bool(net.devices) == compiled
        runner = NgspiceBatch()
        runner.build(net, tmp_path / str(compiled))
        waves[compiled] = runner.run(net, tmp_path / str(compiled))
    u, r, c = 10.0, 1e3, 1e-6
    t = waves[True].time
    assert np.max(np.abs(waves[True]["cap.v"] - u * (1 - np.exp(-t / (r * c))))) <= 1e-4 * u + (5e-6 / (r * c)) ** 2 * u
    assert len(waves[True].time) == len(waves[False].time)
    assert np.max(np.abs(waves[True]["cap.v"] - waves[False]["cap.v"])) <= 1e-9 * u


def test_two_instances_with_their_own_generics(tmp_path: Path):
    """Each junction charges through its resistor to where is0*(exp(v/vt) - 1) = (u0 - v)/r: the steady state of
    each instance with its own generics."""
    from scipy.optimize import brentq

    net = lower(_design(), Analysis(stop=0.2, max_step=1e-4, compiled=True), "t_diode_cap_tb")
    runner = NgspiceBatch()
    runner.build(net, tmp_path)
    w = runner.run(net, tmp_path)
    for name, is0, vt in (("d1", 1e-9, 0.05), ("d2", 2e-8, 0.08)):
        steady = brentq(lambda v, is0=is0, vt=vt: is0 * (np.exp(v / vt) - 1.0) - (1.0 - v) / 1e3, 0.0, 1.0)
        assert w[f"{name}.v"][-1] == pytest.approx(steady, rel=1e-4)


def test_the_one_thread_openmp_shim_changes_no_bit(tmp_path: Path):
    """A run with compiled models loads tools/cosim/one_thread_omp.c before libgomp (ngspice's parallel region around
    each device load on the calling thread): every value of the raw file is the one plain `ngspice -b` writes."""
    net = lower(_design(), Analysis(stop=0.05, max_step=1e-4, compiled=True), "t_diode_cap_tb")
    runner = NgspiceBatch()
    runner.build(net, tmp_path)
    runner.run(net, tmp_path)
    assert list(runner.cache.glob("one_thread_omp-*/one_thread_omp.so"))
    assert "cannot be preloaded" not in (tmp_path / "ngspice.log").read_text()
    shimmed = read_raw(tmp_path / RAW_FILE)
    plain_env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
    subprocess.run(["ngspice", "-b", "netlist.cir"], cwd=tmp_path, env=plain_env, capture_output=True, timeout=60)
    plain = read_raw(tmp_path / RAW_FILE)
    assert shimmed.keys() == plain.keys() and len(plain["time"]) > 100
    for name, values in plain.items():
        np.testing.assert_array_equal(shimmed[name], values)


def test_one_library_serves_every_parameter_set():
    """Generics are instance parameters: other values give the same C code (a study compiles once), another
    structure another code."""
    design = _design()
    values = generic_values(design.top)
    other = {path: {k: v * 1.5 for k, v in generics.items()} for path, generics in values.items()}
    a, b = osdi.device(design.top, values), osdi.device(design.top, other)
    assert a is not None and b is not None
    assert a.code == b.code and a.params != b.params and b.params["p_d2_is0"] == pytest.approx(3e-8)
    single = _design("t_rc_step")
    c = osdi.device(single.top, generic_values(single.top))
    assert c is not None and c.code != a.code


def test_a_construct_the_backend_refuses_is_one_error_at_its_line():
    design = _design()
    model = next(m for m in design.models if m.entity.name == "t_diode_cap")
    eq = model.equations[0]
    model.equations[0] = dataclasses.replace(eq, residual=sy.op("+", eq.residual, sy.Text("x")))
    with pytest.raises(WrsimError, match=r"t_diode_cap\.vhd:21:3: the compiled models \(OSDI\) cannot express"):
        osdi.device(design.top, generic_values(design.top))


def test_a_compiler_failure_is_one_error_naming_the_generated_file(tmp_path: Path):
    with pytest.raises(WrsimError) as err:
        osdi.build("this is not C\n", tmp_path)
    kept = tmp_path / "osdi" / "failed.c"
    assert f"(the generated C file: {kept})" in str(err.value) and kept.read_text() == "this is not C\n"
    assert str(err.value).count(str(kept)) >= 2  # the compiler's own lines name the kept file, not a removed one
    assert not list((tmp_path / "osdi").glob(".*"))  # no staging folder left behind


def test_a_lowered_netlist_with_its_compiled_device_runs_on_its_own(tmp_path: Path):
    out = tmp_path / "motor.cir"
    assert main(["lower", "tb_motor_characteristic", "--stop", "0.01", "--compile", "-o", str(out)]) == 0
    assert (tmp_path / "devices.c").read_text().startswith("/* generated by wrsim")
    proc = subprocess.run(["ngspice", "-b", out.name], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0 and "Error" not in proc.stdout + proc.stderr
    assert (tmp_path / "waveforms.raw").stat().st_size > 0


def test_the_command_line_switch(capsys: pytest.CaptureFixture[str]):
    for flag, compiled in (("--compile", True), ("--no-compile", False)):
        assert main(["lower", "tb_motor_characteristic", "--stop", "0.01", flag]) == 0
        text = capsys.readouterr().out
        assert ("pre_osdi devices.osdi" in text) == compiled
        assert ("\nn_wrsim_equations " in text) == compiled and ("b_ia__eq" in text) != compiled
        assert (" pivrel=1" in text) == compiled  # KLU's pivots chosen by size alone, compiled (netlist.py: why)


def test_a_study_sample_runs_with_the_planning_process_setting(monkeypatch: pytest.MonkeyPatch, tmp_path: Path):
    """A remote Dask worker does not inherit the planning process's WRSIM_COMPILE: the task carries it."""
    from wrsim.study import engine

    seen: list[bool] = []

    def spy(*args, **kwargs):
        seen.append(Analysis(1.0).compiled)
        raise WrsimError("stop here")

    monkeypatch.setattr(engine, "simulate_runs", spy)
    monkeypatch.setenv("WRSIM_COMPILE", "0")
    for compiled in (True, False):
        task = engine.Task(
            "stroke", 0, "s0", {}, load_params(paths.PARAMS / "fpg2_12nm.txt"), workdir=str(tmp_path), compiled=compiled
        )
        assert engine.run_sample(task).error == "stop here"
    assert seen == [True, False] and os.environ["WRSIM_COMPILE"] == "0"
    with compiled_setting(True):
        assert Analysis(1.0).compiled
    assert not Analysis(1.0).compiled


def test_records_made_compiled_are_not_read_as_behavioural(lib):
    """The fleet's record key (plant_digest) holds the compiled-models setting: a store never mixes the two ways;
    the behavioural key is the one it always was (no new term unless compiled)."""
    from wrsim.benches.replay import plant_digest

    with compiled_setting(False):
        behavioural = plant_digest(lib)
    with compiled_setting(True):
        compiled = plant_digest(lib)
    assert behavioural != compiled
    with compiled_setting(False):
        assert plant_digest(lib) == behavioural


def test_an_adc_code_on_its_edge_keeps_its_value_while_newton_straddles_the_edge(tmp_path: Path):
    """A step function of the unknowns (floor, ceil) keeps its last iterate's value at one time point while its
    argument stays within a millionth of its magnitude past an edge (osdi.STEP_HELPER): iterates of a current at
    rest that straddle zero, the edge of code 511 | 512, by their rounding do not flip the code, and with it all ten
    bits of a register, from one iteration to the next (ngspice cut the step to nothing, "timestep too small", in
    the catalog's second attempt at 9 V). Each time point starts from the closed form floor(512 + 512*i), and
    beyond the band the code follows it at once."""
    design = _design("t_adc_register")
    device, inst = _compiled(design, tmp_path)
    row = device.d.nodes[device.nodes.index("code")].resist_off
    base = {n: 0.0 for n in device.nodes}

    def code(i: float, t: float = 1.0) -> float:  # the code the equation asks for at a resistor current i
        device.eval(inst, {**base, "i": i, "a": i}, t)
        return abs(C.c_double.from_address(C.addressof(inst) + row).value)

    assert code(-1e-9) == 511.0  # first iterate: the closed form
    assert code(1e-12) == 511.0  # the next straddles the edge by rounding: kept
    assert code(9e-7) == 511.0  # 1e-6 of the argument 512 is 5e-4 codes: 1e-6 A here
    assert code(2e-6) == 512.0  # past the band: the closed form
    assert code(-1e-12) == 512.0  # and kept back across the edge within it
    assert code(1e-12, t=2.0) == 512.0  # a new time point: the closed form
    assert code(-1e-12, t=3.0) == 511.0
    assert code(-0.5, t=3.0) == 256.0
    assert code(0.5 - 1e-9, t=3.0) == 767.0
