"""Friction and stiffness helpers against the thesis's numbers (4.2.1.2, 4.2.1.3, 4.2.1.5, 4.2.2.1)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wrsim.closed_form.friction import (
    bowden_mu,
    capstan_ratio,
    pulley_efficiency,
    pulley_mu_from_efficiency,
    read_cable_forces,
    read_slider_forces,
    resultant_stiffness,
    slider_friction_fit,
    system_stiffness_from_resultant,
    translational_stiffness,
)
from wrsim.data.measurements import write_table
from wrsim.data.units import convert
from wrsim.errors import WrsimError

# Fig. 4.56 "Slider friction measurement result" (drum torque 1.18 .. 15 N*m), rail B of a front door
LOAD = np.array([0, 152, 189, 221, 247, 281, 310, 347, 386, 410, 449.0])
TOP = np.array([82.6, 271, 310, 347, 375, 413, 448, 490, 534, 568, 605])
BOTTOM = np.array([77.3, 148, 162, 177, 189, 205, 216, 230, 246, 265, 276])
DIFF_OVER_SHARE = [8.83, 205.00, 246.67, 283.33, 310.00, 346.67, 386.67, 433.33, 480.00, 505.00, 548.33]
N_PER_MM = "N/mm"


def test_slider_fig4_56_linear_fit_r_squared():
    fit = slider_friction_fit(LOAD, TOP, BOTTOM, share=0.6)
    assert fit.r_squared == pytest.approx(0.9992, abs=5e-5)  # thesis: "squared residual of 0.9992"
    assert fit.r_squared == pytest.approx(0.999175, abs=1e-6)  # measured over all 11 rows
    assert fit.slope == pytest.approx(0.71745, abs=1e-5)
    assert fit.intercept == pytest.approx(9.609, abs=1e-3)  # N
    # the table's last row is the B-pillar difference divided by slider B's 60 % share
    np.testing.assert_allclose((TOP - BOTTOM) / 0.6, DIFF_OVER_SHARE, atol=0.006)
    # friction of slider B (Eq. 4.40): F_r = F_up - F_dw - 0.6*F_load, linear in its load 0.6*F_load
    assert fit.share == 0.6
    assert fit.friction_offset == pytest.approx(9.609, abs=1e-3)  # N (no-load row alone: 5.3 N, "about 5 N")
    assert fit.friction_slope == pytest.approx(0.19574, abs=1e-5)
    assert fit.friction_r_squared == pytest.approx(0.97011, abs=1e-5)
    # "only middle and high range" (without the no-load row) gives 0.99925, also ~0.9992
    assert slider_friction_fit(LOAD[1:], TOP[1:], BOTTOM[1:], 0.6).r_squared == pytest.approx(0.999251, abs=1e-6)


def test_slider_errors():
    with pytest.raises(WrsimError, match=r"share must be in \(0, 1\], got 1.5"):
        slider_friction_fit(LOAD, TOP, BOTTOM, 1.5)
    with pytest.raises(WrsimError, match="differ in length"):
        slider_friction_fit(LOAD, TOP[:-1], BOTTOM, 0.6)
    with pytest.raises(WrsimError, match="the load force must vary"):
        slider_friction_fit([5.0, 5.0], [10.0, 11.0], [1.0, 2.0], 0.6)


def test_pulley_mu_from_force_ratio():
    wrap = math.radians(162)
    # thesis 4.2.1.3: eta = 0.96, wrap 162 deg, pulley 40 mm, shaft 12 mm -> mu = 0.069
    mu = pulley_mu_from_efficiency(0.96, wrap, r_in=0.006, r_out=0.020)
    assert mu == pytest.approx(0.069, abs=5e-4)
    assert mu == pytest.approx(0.068875, abs=1e-6)
    assert pulley_efficiency(mu, wrap, 0.006, 0.020) == pytest.approx(0.96, abs=1e-12)
    # the suggested simulation range 0.04 .. 0.15 maps to force ratios 0.977 .. 0.915
    assert pulley_efficiency(0.04, wrap, 0.006, 0.020) == pytest.approx(0.97657, abs=1e-5)
    assert pulley_efficiency(0.15, wrap, 0.006, 0.020) == pytest.approx(0.91489, abs=1e-5)
    assert pulley_efficiency(0.0, wrap, 0.006, 0.020) == 1.0


def test_pulley_errors():
    with pytest.raises(WrsimError, match=r"eta = F_b/F_a must be in \(0, 1\], got 1.1"):
        pulley_mu_from_efficiency(1.1, 1.0, 0.006, 0.02)
    with pytest.raises(WrsimError, match="need 0 < r_in < r_out"):
        pulley_mu_from_efficiency(0.9, 1.0, 0.02, 0.006)
    with pytest.raises(WrsimError, match=r"wrap angle must be in \(0, 2\*pi\]"):
        pulley_efficiency(0.1, 7.0, 0.006, 0.02)
    with pytest.raises(WrsimError, match="mu\\*r_in/r_out < 1"):
        pulley_efficiency(5.0, 1.0, 0.006, 0.02)


def test_bowden_capstan_law():
    # thesis 4.2.1.2, Fig. 4.50: mu 0.08 at 20 .. 80 degC, 0.20 at -30 degC, measured with a 180 deg wrap
    assert capstan_ratio(0.08, math.pi) == pytest.approx(1.28573, abs=1e-5)  # Eq. 4.37a
    assert 1 / capstan_ratio(0.08, math.pi) == pytest.approx(0.77777, abs=1e-5)  # efficiency, Eq. 4.38b
    assert capstan_ratio(0.20, math.pi) == pytest.approx(1.87446, abs=1e-5)
    f_b = np.array([40.0, 60.0, 80.0])
    assert bowden_mu(f_b * capstan_ratio(0.20, math.pi), f_b, math.pi) == pytest.approx(0.20, abs=1e-12)
    assert bowden_mu(50.0 * math.exp(0.08 * math.pi), 50.0, math.pi) == pytest.approx(0.08, abs=1e-12)
    with pytest.raises(WrsimError, match=r"sample 2: need F_a >= F_b > 0 \(pulling side first\)"):
        bowden_mu([60.0, 40.0], [50.0, 50.0], math.pi)
    with pytest.raises(WrsimError, match="must be >= 0"):
        capstan_ratio(-0.1, math.pi)


def test_system_stiffness_eq_4_42():
    # thesis 4.2.2.1, Fig. 4.60: resultant 6.9 N/mm, gauge 10 N/mm, damper 0.8 N*m/deg at r = 20 mm
    damper = translational_stiffness(convert(0.8, "N*m/deg", "N*m/rad"), 0.020)
    assert convert(damper, "N/m", N_PER_MM) == pytest.approx(114.591, abs=1e-3)  # thesis: 114.591 N/mm
    c2 = system_stiffness_from_resultant(convert(6.9, N_PER_MM, "N/m"), convert(10, N_PER_MM, "N/m"), damper)
    assert convert(c2, "N/m", N_PER_MM) == pytest.approx(27.6236, abs=1e-4)  # thesis: 27.6236 N/mm
    assert convert(resultant_stiffness(10e3, c2, damper), "N/m", N_PER_MM) == pytest.approx(6.9, abs=1e-12)
    assert resultant_stiffness(2.0, 2.0) == pytest.approx(1.0)
    with pytest.raises(WrsimError, match="not softer than gauge"):
        system_stiffness_from_resultant(10e3, 10e3, damper)
    with pytest.raises(WrsimError, match="need one or more stiffnesses > 0"):
        resultant_stiffness(1.0, 0.0)
    with pytest.raises(WrsimError, match="radius must be > 0"):
        translational_stiffness(1.0, 0.0)


def test_read_slider_forces(tmp_path):
    path = tmp_path / "slider.csv"
    write_table(
        path,
        {"load_force": LOAD / 1000, "force_top": TOP, "force_bottom": BOTTOM},
        {"load_force": "kN", "force_top": "N", "force_bottom": "N"},
        ["source: thesis Fig. 4.56"],
    )
    load, top, bottom = read_slider_forces(path)
    np.testing.assert_allclose(load, LOAD)
    assert slider_friction_fit(load, top, bottom, 0.6).r_squared == pytest.approx(0.999175, abs=1e-6)

    write_table(path, {"load_force": LOAD, "force_top": TOP}, {"load_force": "N", "force_top": "N"}, ["source: x"])
    with pytest.raises(WrsimError, match=r"slider.csv: a slider friction measurement .* missing: force_bottom"):
        read_slider_forces(path)
    falling = LOAD.copy()
    falling[3] = 100.0
    write_table(
        path,
        {"load_force": falling, "force_top": TOP, "force_bottom": BOTTOM},
        {"load_force": "N", "force_top": "N", "force_bottom": "N"},
        ["source: x"],
    )
    with pytest.raises(WrsimError, match=r"slider.csv:6: column 'load_force': 100 does not increase"):
        read_slider_forces(path)
    write_table(
        path,
        {"load_force": LOAD, "force_top": TOP, "force_bottom": BOTTOM},
        {"load_force": "N", "force_top": "N*m", "force_bottom": "N"},
        ["source: x"],
    )
    with pytest.raises(WrsimError, match=r"column 'force_top': cannot convert 'N\*m'"):
        read_slider_forces(path)


def test_read_cable_forces(tmp_path):
    path = tmp_path / "pulley.csv"
    write_table(
        path,
        {"force_a": [5.208, 5.21], "force_b": [5.0, 5.0]},
        {"force_a": "daN", "force_b": "daN"},
        ["source: unit test"],
    )
    f_a, f_b = read_cable_forces(path)
    np.testing.assert_allclose(f_a, [52.08, 52.1])
    assert pulley_mu_from_efficiency(float(np.mean(f_b / f_a)), math.radians(162), 0.006, 0.02) == pytest.approx(
        0.069, abs=1e-3
    )
    write_table(path, {"force_a": [1.0, 2.0]}, {"force_a": "N"}, ["source: unit test"])
    with pytest.raises(WrsimError, match="cable-force measurement .* missing: force_b"):
        read_cable_forces(path)
