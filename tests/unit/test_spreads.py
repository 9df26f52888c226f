"""Tolerance studies without a simulator: the tolerance grammar of parameter sets and its errors, the draws (laws,
groups, tables, reproducibility), the sensitivity and worst-case plans, the ambient temperature, the statistics."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import binomtest

from wrsim import paths
from wrsim.data.params import load_params
from wrsim.data.temperature import at_temperature
from wrsim.errors import WrsimError
from wrsim.study import Study, StudySpec, draw, factors, sample_set, sensitivity_plan, units, worst_case_plan
from wrsim.study.report import statistics

BASE = """\
[dcpm_motor]
ke = 0.02 V*s/rad
kt = 0.02 N*m/A
ra = 0.8 Ohm
mc = 0.01 N*m
[seal_friction]
forces = [15.0, 65.0] N
[ambient]
temperature = 20 degC
"""
SPREADS = """\
[dcpm_motor]
ke +- 6 % group magnet
kt +- 6 % group magnet
ra +- 0.08 Ohm normal 2sigma
mc +- 0.002 N*m uniform
[seal_friction]
forces +- 30 %
[ambient]
temperature in -30 .. 80 degC
"""


def write(tmp_path: Path, text: str, name: str) -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture
def pset(tmp_path):
    return load_params(write(tmp_path, BASE, "base.txt")).overlay(
        load_params(write(tmp_path, SPREADS, "tol.txt")), user=True
    )


def test_grammar_keeps_the_nominal_value_and_reads_the_spread(tmp_path):
    p = load_params(
        write(
            tmp_path,
            "[dcpm_motor]\nra = 0.55 Ohm +- 5 % normal 3sigma  # comment\n"
            "[ambient]\ntemperature = 20 degC in -30 .. 80 degC uniform\n",
            "a.txt",
        )
    )
    assert p.sections["dcpm_motor"]["ra"].value == 0.55 and p.sections["dcpm_motor"]["ra"].unit == "Ohm"
    t = p.tolerances["dcpm_motor"]["ra"]
    assert (t.law, t.deviation, t.relative, t.sigmas, t.line) == ("normal", 0.05, True, 3.0, 2)
    t = p.tolerances["ambient"]["temperature"]
    assert (t.law, t.limits, t.unit) == ("uniform", (-30.0, 80.0), "degC")


def test_a_spread_only_line_needs_a_nominal_value_beneath(tmp_path, pset):
    alone = load_params(write(tmp_path, SPREADS, "alone.txt"))
    with pytest.raises(WrsimError, match=r"alone.txt:2: \[dcpm_motor\] ke: a tolerance without a nominal value"):
        factors(alone)
    assert [f.name for f in factors(pset)] == [
        "ambient.temperature",
        "dcpm_motor.ke",
        "dcpm_motor.kt",
        "dcpm_motor.mc",
        "dcpm_motor.ra",
        "seal_friction.forces",
    ]


@pytest.mark.parametrize(
    "line, message",
    [
        ("ra = 0.5 Ohm +- -5 %", r"the tolerance -5 must be > 0"),
        ("ra = 0.5 Ohm +- 5", r"write '\+- N %' or '\+- N <unit>'"),
        ("ra = 0.5 Ohm +- 5 % lognormal", r"'lognormal' is not part of a tolerance"),
        ("ra = 0.5 Ohm +- 5 % normal 0sigma", r"the tolerance is 0\.5 \.\. 10 standard deviations"),
        ("ra = 0.5 Ohm +- 0.1 N*m", r"tolerance in 'N\*m' for a value in 'Ohm'"),
        ("ra = 0.5 Ohm +- 0.1 Ohmx", r"tolerance: unknown unit 'Ohmx'"),
        ("ra = 0.5 Ohm in 0.6 .. 0.9 Ohm", r"the nominal 0.5 Ohm is outside the range 0.6 .. 0.9 Ohm"),
        ("ra = 0.5 Ohm in 0.9 .. 0.1 Ohm", r"the lower limit must be below the upper"),
        ("ra = 0.5 Ohm in 0.1 .. 0.9 Ohm normal", r"a range 'in LOW .. HIGH' is uniform"),
        ("ra = 0.5 Ohm +- 5 % group g 1.5", r"group correlation 1.5 is outside -1 .. 1"),
        ("ra = 0.5 Ohm from nofile.csv", r"write 'from FILE.csv:COLUMN'"),
        ("ra = 0.5 Ohm from motors.csv:rb", r"no column 'rb'"),
        ("ra +- 5 %\nra +- 6 %", r":3: \[dcpm_motor\] ra: duplicate tolerance \(first on line 2\)"),
    ],
)
def test_bad_spreads_name_file_line_and_key(tmp_path, line, message):
    write(tmp_path, "ra[Ohm],ke[V*s/rad]\n0.5,0.02\n", "motors.csv")
    path = write(tmp_path, f"[dcpm_motor]\n{line}\n", "bad.txt")
    with pytest.raises(WrsimError, match=message) as e:
        load_params(path)
    assert str(path) in str(e.value) and "[dcpm_motor] ra" in str(e.value)


def test_draws_follow_their_laws(pset):
    fs = factors(pset)
    draws = [draw(fs, 7, i) for i in range(4000)]
    ra = np.array([d["dcpm_motor.ra"] for d in draws])
    assert abs(ra.mean() - 0.8) < 0.003 and abs(ra.std() / 0.04 - 1.0) < 0.05  # +-0.08 Ohm = 2 sigma
    mc = np.array([d["dcpm_motor.mc"] for d in draws])
    assert 0.008 <= mc.min() and mc.max() <= 0.012 and abs(mc.std() / (0.002 / math.sqrt(3)) - 1.0) < 0.05
    temp = np.array([d["ambient.temperature"] for d in draws])
    assert -30.0 <= temp.min() < -29.0 and 79.0 < temp.max() <= 80.0 and abs(temp.mean() - 25.0) < 2.0
    ke = np.array([d["dcpm_motor.ke"] for d in draws])
    kt = np.array([d["dcpm_motor.kt"] for d in draws])
    np.testing.assert_allclose(ke / 0.02, kt / 0.02, rtol=1e-12)  # one group draw, correlation 1
    assert abs(ke.std() / 0.02 / 0.02 - 1.0) < 0.05  # +-6 % = 3 sigma
    forces = np.array([d["seal_friction.forces"] for d in draws])
    np.testing.assert_allclose(forces[:, 1] / forces[:, 0], 65.0 / 15.0)  # a list moves as a whole


def test_draws_are_reproducible_per_sample(pset):
    """A sample's draw depends on the seed and its index alone: the same from factors built again, in any order of
    the samples; another seed or another index draws other values."""
    fs = factors(pset)
    assert draw(fs, 3, 17) == draw(factors(pset), 3, 17)
    assert [draw(fs, 3, i) for i in range(5)] == [draw(fs, 3, i) for i in reversed(range(5))][::-1]
    assert draw(fs, 3, 17) != draw(fs, 4, 17) and draw(fs, 3, 17) != draw(fs, 3, 18)


def test_partial_correlation_and_table_rows(tmp_path):
    write(
        tmp_path,
        "# five motors\nke[V*s/rad],kt[N*m/A]\n0.019,0.0171\n0.020,0.0172\n0.021,0.0173\n0.022,0.0174\n0.023,0.0175\n",
        "motors.csv",
    )
    p = load_params(
        write(
            tmp_path,
            "[dcpm_motor]\nke = 0.02 V*s/rad from motors.csv:ke group unit\n"
            "kt = 0.017 N*m/A from motors.csv:kt group unit\nra = 0.8 Ohm +- 9 % group r 0.5\n"
            "j = 1e-5 kg*m**2 +- 9 % group r 0.5\n",
            "m.txt",
        )
    )
    fs = factors(p)
    draws = [draw(fs, 1, i) for i in range(4000)]
    rows = {(round(d["dcpm_motor.ke"], 6), round(d["dcpm_motor.kt"], 6)) for d in draws}
    assert rows == {(round(0.019 + k * 1e-3, 6), round(0.0171 + k * 1e-4, 6)) for k in range(5)}  # whole rows
    ra, j = (np.array([d[f"dcpm_motor.{k}"] for d in draws]) for k in ("ra", "j"))
    assert abs(np.corrcoef(ra, j)[0, 1] - 0.25) < 0.05  # 0.5 * 0.5 through the group draw


def test_sensitivity_moves_a_group_together_and_worst_case_follows_the_effects(pset):
    fs = factors(pset)
    names = [name for name, _ in units(fs)]
    assert names == ["ambient.temperature", "group magnet", "dcpm_motor.mc", "dcpm_motor.ra", "seal_friction.forces"]
    plan = dict(sensitivity_plan(fs))
    assert len(plan) == 1 + 2 * len(names)
    assert plan["group magnet high"]["dcpm_motor.ke"] == pytest.approx(0.0212)
    assert plan["group magnet high"]["dcpm_motor.kt"] == pytest.approx(0.0212)
    assert plan["dcpm_motor.ra low"]["dcpm_motor.ra"] == pytest.approx(0.72)  # +-0.08 Ohm
    assert plan["ambient.temperature low"]["ambient.temperature"] == -30.0
    effects = {
        "time": {
            "dcpm_motor.ra": 0.3,
            "group magnet": -0.1,
            "dcpm_motor.mc": 0.0,
            "ambient.temperature": math.nan,
            "seal_friction.forces": 0.2,
        },
        "none": {},
    }
    corners = dict(worst_case_plan(fs, effects))
    assert set(corners) == {"time lowest", "time highest"}
    high = corners["time highest"]
    assert high["dcpm_motor.ra"] == pytest.approx(0.88) and high["dcpm_motor.ke"] == pytest.approx(0.0188)
    assert high["seal_friction.forces"] == pytest.approx([19.5, 84.5])
    assert high["dcpm_motor.mc"] == 0.01 and high["ambient.temperature"] == 20.0  # no effect: nominal


def test_sample_set_replaces_values_also_in_the_users_set(pset):
    s = sample_set(pset, {"dcpm_motor.ra": 0.9, "seal_friction.forces": [16.0, 70.0]}, "x")
    assert s.number_in("dcpm_motor", "ra", "Ohm") == 0.9 and s.tolerances == {}
    assert pset.number_in("dcpm_motor", "ra", "Ohm") == 0.8
    beneath = s.beneath(load_params(paths.ALGORITHMS / "observer.txt"))  # a run's own set: the user's on top
    assert beneath.number_in("dcpm_motor", "ra", "Ohm") == 0.9


def test_ambient_temperature_applies_the_derived_sets_rules():
    base = load_params(paths.PARAMS / "rail_wr_8p5nm.txt")
    cold = load_params(paths.PARAMS / "rail_wr_8p5nm_m30c.txt")
    ambient = base.overlay(load_params(paths.PARAMS / "tolerances" / "ambient.txt"))
    assert "ambient" not in at_temperature(ambient).sections
    assert at_temperature(ambient).sections == base.sections  # 20 degC: the set as it is
    at = at_temperature(sample_set(ambient, {"ambient.temperature": -30.0}, "cold"))
    for entity, key in (
        ("dcpm_motor", "ra"),
        ("dcpm_motor", "ke"),
        ("dcpm_motor", "kt"),
        ("bowden", "mu"),
        ("rubber_damper", "stiffness"),
        ("drive", "m_gc"),
        ("seal_friction", "forces"),
        ("top_frame_seal", "frictions"),
        ("dcpm_motor", "laa"),
    ):
        np.testing.assert_allclose(
            at.value_in(entity, key, cold.sections[entity][key].unit),
            cold.value_in(entity, key, cold.sections[entity][key].unit),
            rtol=1e-6,
        )
    with pytest.raises(WrsimError, match=r"ambient.txt:\d+: \[ambient\] temperature: 90 degC is outside -40 .. 85"):
        at_temperature(sample_set(ambient, {"ambient.temperature": 90.0}, "hot"))


def _study(rows: dict[int, dict], outputs: dict, limits=()) -> Study:
    return Study(StudySpec("stroke", limits=limits), Path("/nonexistent"), [], rows, outputs)


def test_statistics_cpk_percentiles_and_probability():
    rng = np.random.default_rng(0)
    t = rng.normal(4.0, 0.1, 500)
    rows = {
        k: {
            "sample": k,
            "label": f"mc{k}",
            "error": "",
            "outputs": {"time": float(t[k]), "reversed": float(k % 10 == 0)},
        }
        for k in range(500)
    }
    rows[500] = {"sample": 500, "label": "mc500", "error": "failed", "outputs": {}}
    meta = {
        "time": {"unit": "s", "lower": 3.5, "upper": 4.5, "note": ""},
        "reversed": {"unit": "1", "lower": None, "upper": 0.5, "note": ""},
    }
    s = {x.name: x for x in statistics(_study(rows, meta))}
    assert s["time"].n == 500 and s["time"].mean == pytest.approx(t.mean())
    assert s["time"].cpk == pytest.approx(min(4.5 - t.mean(), t.mean() - 3.5) / (3 * t.std(ddof=1)))
    assert s["time"].percentiles[95] == pytest.approx(np.percentile(t, 95))
    assert s["time"].outside == int(np.sum((t < 3.5) | (t > 4.5)))
    worst = s["time"].worst[0]
    assert worst[0] == int(np.argmin(np.minimum(4.5 - t, t - 3.5)))
    ci = binomtest(50, 500).proportion_ci(0.95)
    assert s["reversed"].probability == pytest.approx((0.1, ci.low, ci.high)) and s["reversed"].cpk is None
    limited = {x.name: x for x in statistics(_study(rows, meta, limits=(("time", None, 4.2),)))}
    assert limited["time"].lower is None and limited["time"].cpk == pytest.approx(
        (4.2 - t.mean()) / (3 * t.std(ddof=1))
    )
