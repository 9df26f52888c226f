"""The IEEE 1076.1.1 packages of vhdl/ieee: for each, a small testbench that uses it runs with `wrsim run` and
matches its closed form; the fundamental constants match scipy.constants within three of the uncertainties the
standard states for its (CODATA 1998) values."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest
import scipy.constants as sc

from wrsim.cli import main

THERMAL = """library ieee; use ieee.thermal_systems.all;
entity th_tb is generic (p : heat_flow := 10.0; r : thermal_resistance := 2.0; c : thermal_capacitance := 0.05);
end entity th_tb;
architecture a of th_tb is
  terminal n : thermal;
  quantity qs through thermal_ref to n;
  quantity t across q through n to thermal_ref;
begin
  if domain = quiescent_domain use qs == 0.0; else qs == p; end use;
  q == c * t'dot + t / r;
end architecture a;"""
FLUIDIC = """library ieee; use ieee.fluidic_systems.all;
entity fl_tb is generic (p0 : pressure := 2.0e5; r : fresistance := 1.0e8; c : fcapacitance := 1.0e-9;
                         m0 : mass_flow_rate := 0.5; cr : cfresistance := 4.0e5; cc : cfcapacitance := 1.0e-6);
end entity fl_tb;
architecture a of fl_tb is
  terminal inlet, tank : fluidic;
  terminal vessel : compressible_fluidic;
  quantity ps across qs through inlet to fluidic_ref;    quantity dp across qp through inlet to tank;
  quantity p across qt through tank to fluidic_ref;      quantity ms through compressible_fluidic_ref to vessel;
  quantity pv across mv through vessel to compressible_fluidic_ref;
begin
  if domain = quiescent_domain use ps == 0.0; ms == 0.0; else ps == p0; ms == m0; end use;
  dp == r * qp;    qt == c * p'dot;    mv == cc * pv'dot + pv / cr;
end architecture a;"""
RADIANT = """library ieee; use ieee.radiant_systems.all;
entity ra_tb is generic (e : illuminance := 500.0; area : real := 0.02; omega : real := 3.0); end entity ra_tb;
architecture a of ra_tb is
  terminal n : radiant;
  quantity phi through radiant_ref to n;    quantity iv across phil through n to radiant_ref;
begin
  phi == e * area * now;    iv == phil / omega;
end architecture a;"""
ENERGY = """library ieee; use ieee.energy_systems.all;
entity en_tb is generic (f0 : real := 3.0; c : real := 0.5; g : real := 2.0); end entity en_tb;
architecture a of en_tb is
  terminal n : unspecified;
  quantity fs through unspecified_ref to n;    quantity x across f through n to unspecified_ref;
  quantity stored : energy;    quantity p_in : power;
begin
  if domain = quiescent_domain use fs == 0.0; else fs == f0; end use;
  f == c * x'dot + g * x;    stored == 0.5 * c * x * x;    p_in == x * fs;
end architecture a;"""
MAGNETIC = """library ieee; use ieee.electrical_systems.all;
entity mag_tb is generic (u : voltage := 1.0; r : resistance := 10.0; n : real := 100.0; rm : reluctance := 1.0e6);
end entity mag_tb;
architecture a of mag_tb is
  terminal a, b : electrical;
  terminal m : magnetic;
  quantity vs across isrc through a to ground;    quantity vr across ir through a to b;
  quantity vc across ic through b to ground;      quantity fc across phic through m to magnetic_ref;
  quantity fr across phi through m to magnetic_ref;
begin
  if domain = quiescent_domain use vs == 0.0; else vs == u; end use;
  vr == r * ir;    fc == n * ic;    vc == n * phi'dot;    fr == rm * phi;
end architecture a;"""
MECHANICAL = """library ieee; use ieee.mechanical_systems.all;
entity me_tb is generic (f0 : force := 4.0; m : mass := 2.0; b : damping := 8.0); end entity me_tb;
architecture a of me_tb is
  terminal n : translational_v;
  quantity fs through translational_v_ref to n;    quantity v across f through n to translational_v_ref;
  quantity p : momentum;
begin
  if domain = quiescent_domain use fs == 0.0; else fs == f0; end use;
  f == m * v'dot + b * v;    p == m * v;
end architecture a;"""
CONSTANTS = """library ieee; use ieee.fundamental_constants.all;
entity co_tb is end entity co_tb;
architecture a of co_tb is
  quantity q, k, eps0, mu0, c, h, g, ctok, vt : real;
begin
  q == phys_q * 1.0e19; k == phys_k * 1.0e23; eps0 == phys_eps0 * 1.0e12; mu0 == phys_mu0 * 1.0e6;
  c == phys_c * 1.0e-8; h == phys_h_over_2_pi * 1.0e34; g == phys_gravity; ctok == phys_ctok;
  vt == phys_k * 300.0 / phys_q;
end architecture a;"""
MATERIAL = """library ieee; use ieee.thermal_systems.all, ieee.material_constants.all;
entity mat_tb is generic (t0 : temperature := 350.0; r : thermal_resistance := 4.0; c : thermal_capacitance := 0.05);
end entity mat_tb;
architecture a of mat_tb is
  terminal body_n, amb : thermal;
  quantity ta across qa through amb to thermal_ref;    quantity t across qc through body_n to thermal_ref;
  quantity dt across qr through body_n to amb;         quantity eps : real;
begin
  ta == ambient_temperature;    qc == c * t'dot;    dt == r * qr;
  eps == phys_eps_sio2 * ambient_pressure / 1.0e5;
  break t => t0;
end architecture a;"""


def _rise(t, tau):
    return 1.0 - np.exp(-t / tau)


# top -> (testbench, stop [s], column -> its closed form of t), each within 1e-3 of its largest magnitude
CASES = {
    "th_tb": (THERMAL, 0.5, {"t": lambda t: 20.0 * _rise(t, 0.1)}),
    "fl_tb": (FLUIDIC, 0.5, {"p": lambda t: 2.0e5 * _rise(t, 0.1), "pv": lambda t: 2.0e5 * _rise(t, 0.4)}),
    "ra_tb": (RADIANT, 1.0, {"iv": lambda t: 500.0 * 0.02 * t / 3.0}),
    "en_tb": (
        ENERGY,
        1.0,
        {
            "x": lambda t: 1.5 * _rise(t, 0.25),
            "stored": lambda t: 0.25 * (1.5 * _rise(t, 0.25)) ** 2,
            "p_in": lambda t: 3.0 * 1.5 * _rise(t, 0.25),
        },
    ),
    "mag_tb": (MAGNETIC, 5e-3, {"ic": lambda t: 0.1 * _rise(t, 1e-3), "phi": lambda t: 1e-5 * _rise(t, 1e-3)}),
    "me_tb": (MECHANICAL, 1.0, {"v": lambda t: 0.5 * _rise(t, 0.25), "p": lambda t: 1.0 * _rise(t, 0.25)}),
    "mat_tb": (MATERIAL, 1.0, {"t": lambda t: 298.15 + 51.85 * np.exp(-t / 0.2), "eps": lambda t: 3.9 + 0.0 * t}),
}


def _simulate(tmp_path: Path, text: str, top: str, stop: float) -> dict[str, np.ndarray]:
    """`wrsim run` of `text` (top `top`) to `stop`: the waveform table, column name (without '_<top>[unit]') ->
    values, 'time' -> the time points."""
    (tmp_path / f"{top}.vhd").write_text(text + "\n")
    status = main(
        [
            "run",
            str(tmp_path / f"{top}.vhd"),
            "--top",
            top,
            "--stop",
            repr(stop),
            "--max-step",
            repr(stop / 1000),
            "--results",
            str(tmp_path / "out"),
        ]
    )
    assert status == 0
    with (tmp_path / "out" / "run" / top / "waveforms.csv").open() as f:
        rows = list(csv.reader(f))
    data = np.array(rows[1:], dtype=float)
    return {h.split("[")[0].removesuffix(f"_{top}"): data[:, k] for k, h in enumerate(rows[0])}


@pytest.mark.parametrize("top", CASES)
def test_a_testbench_using_the_package_matches_its_closed_form(top, tmp_path):
    text, stop, checks = CASES[top]
    waves = _simulate(tmp_path, text, top, stop)
    for column, ref in checks.items():
        expected = ref(waves["time"])
        np.testing.assert_allclose(
            waves[column], expected, rtol=0, atol=1e-3 * np.max(np.abs(expected)), err_msg=f"{top}: {column}"
        )


def test_fundamental_constants_match_codata_within_their_stated_uncertainty(tmp_path):
    last = {k: v[-1] for k, v in _simulate(tmp_path, CONSTANTS, "co_tb", 1e-3).items()}
    # the standard's stated uncertainties, relative (for hbar: h's, as in CODATA 1998)
    sigma = {"q": 0.000_000_063 / 1.602_176_462, "k": 0.000_002_4 / 1.380_650_3, "h": 0.000_000_52 / 6.626_068_76}
    checks = {  # column: (scipy's current CODATA value, its scale in the testbench, relative tolerance)
        "q": (sc.e, 1e19, 3 * sigma["q"]),
        "k": (sc.k, 1e23, 3 * sigma["k"]),
        "h": (sc.hbar, 1e34, 3 * sigma["h"]),
        "eps0": (sc.epsilon_0, 1e12, 1e-9),
        "mu0": (sc.mu_0, 1e6, 1e-9),
        "c": (sc.c, 1e-8, 1e-12),
        "g": (sc.g, 1.0, 1e-12),
        "ctok": (sc.zero_Celsius, 1.0, 1e-12),
        "vt": (sc.k * 300.0 / sc.e, 1.0, 3 * sigma["k"]),
    }
    for name, (value, scale, rtol) in checks.items():
        assert math.isclose(last[name], value * scale, rel_tol=rtol), f"phys_{name}: {last[name]} vs {value * scale}"
