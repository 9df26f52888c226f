"""The compiled models (wrsim.backend.ngspice.osdi): each architecture's equations as an OSDI device.

The device code is checked through its own descriptor (loaded with ctypes, as ngspice's loader reads it):
residuals and Jacobian entries against the closed form of a nonlinear junction with a 'dot in its reactive part,
with a generic per instance. Whole runs are checked against closed forms and against the behavioural netlist;
the corpus runs compiled in tests/unit/test_corpus.py."""

from __future__ import annotations

import ctypes as C
import dataclasses
from pathlib import Path

import numpy as np
import pytest

from conftest import ANALYTIC, _library
from wrsim.backend.ngspice import osdi
from wrsim.backend.ngspice.batch import NgspiceBatch
from wrsim.backend.ngspice.netlist import Analysis, lower
from wrsim.cli import main
from wrsim.elab import elaborate
from wrsim.elab import symbolic as sy
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

    def __call__(self, x: dict[str, float], params: dict[int, float], t: float = 1.0) -> _Eval:
        d, n = self.d, self.d.num_nodes
        inst = (C.c_char * d.instance_size)()
        base = C.addressof(inst)
        mapping = (_U32 * n).from_address(base + d.node_mapping_offset)
        for k in range(n):
            mapping[k] = k + 1  # equation 0 is ground
        for pid, value in params.items():
            C.c_double.from_address(d.access(base, None, pid, 1 | 4)).value = value
        d.setup_instance(None, base, None, 300.0, n, None, C.addressof(_InitInfo()))
        solution = (C.c_double * (n + 1))(0.0, *[x[name] for name in self.nodes])
        info = _Info(abstime=t, prev_solve=solution)
        d.eval(None, base, None, C.addressof(info))
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
def junction(tmp_path_factory: pytest.TempPathFactory) -> tuple[_Device, osdi.Device]:
    design = _design()
    model = next(m for m in design.models if m.entity.name == "t_diode_cap")
    dev = osdi.device(model)
    assert dev is not None
    lib = osdi.build(osdi.library([dev]), tmp_path_factory.mktemp("osdi"))
    return _Device(lib, dev.name), dev


@pytest.mark.parametrize("is0, vt, c0", [(1e-9, 0.05, 1e-6), (2e-8, 0.08, 3e-6)])
def test_junction_residuals_and_jacobian_match_the_closed_form(junction, is0: float, vt: float, c0: float):
    device, dev = junction
    assert device.nodes == ["i", "p", "n", "v__dot"] and dev.params == ["c0", "is0", "vt"]
    params = {1: c0, 2: is0, 3: vt}  # 0 is $mfactor
    rng = np.random.default_rng(7)
    for _ in range(20):
        x = dict(zip(device.nodes, rng.normal(0.0, [1e-3, 0.2, 0.2, 50.0]), strict=True))
        v = x["p"] - x["n"]
        e = device(x, params)
        i_law = is0 * (np.exp(v / vt) - 1.0) + c0 * x["v__dot"]
        # the equation's row carries i - law (or its negative); the terminals the through current; the 'dot node
        # its own value (F) against the across quantity (Q = -v)
        assert abs(abs(e.F[0]) - abs(x["i"] - i_law)) <= 1e-12 * (1 + abs(i_law))
        sign = 1.0 if e.F[0] * (x["i"] - i_law) >= 0 else -1.0
        assert e.F[1:].tolist() == pytest.approx([x["i"], -x["i"], x["v__dot"]], rel=1e-15, abs=1e-300)
        assert e.Q.tolist() == pytest.approx([0.0, 0.0, 0.0, -v], abs=1e-15)
        slope = is0 / vt * np.exp(v / vt)
        assert e.JF[0].tolist() == pytest.approx([sign, -sign * slope, sign * slope, -sign * c0], rel=1e-12)
        assert e.JQ[3].tolist() == pytest.approx([0.0, -1.0, 1.0, 0.0])
        # and the Jacobian is the derivative of the residual (central differences)
        for k, name in enumerate(device.nodes):
            h = 1e-6 * max(1.0, abs(x[name]))
            up, down = device({**x, name: x[name] + h}, params), device({**x, name: x[name] - h}, params)
            assert (up.F - down.F) / (2 * h) == pytest.approx(e.JF[:, k], rel=1e-5, abs=1e-9)


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


def test_a_construct_the_backend_refuses_is_one_error_at_its_line():
    design = _design()
    model = next(m for m in design.models if m.entity.name == "t_diode_cap")
    eq = model.equations[0]
    bad = dataclasses.replace(eq, residual=sy.op("+", eq.residual, sy.Text("x")))
    with pytest.raises(WrsimError, match=r"t_diode_cap\.vhd:21:3: the compiled models \(OSDI\) cannot express"):
        osdi.device(dataclasses.replace(model, equations=[bad]))


def test_a_compiler_failure_is_one_error_naming_the_generated_file(tmp_path: Path):
    with pytest.raises(WrsimError) as err:
        osdi.build("this is not C\n", tmp_path)
    kept = tmp_path / "osdi" / "failed.c"
    assert f"(the generated C file: {kept})" in str(err.value) and kept.read_text() == "this is not C\n"
    assert not list((tmp_path / "osdi").glob(".*"))  # no staging folder left behind


def test_the_command_line_switch(capsys: pytest.CaptureFixture[str]):
    for flag, compiled in (("--compile", True), ("--no-compile", False)):
        assert main(["lower", "tb_motor_characteristic", "--stop", "0.01", flag]) == 0
        text = capsys.readouterr().out
        assert ("pre_osdi devices.osdi" in text) == compiled
        assert ("\nn_wrsim_dcpm_motor " in text) == compiled and ("b_ia__eq" in text) != compiled
