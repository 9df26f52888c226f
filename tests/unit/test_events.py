"""Events on the analog side (IEEE 1076.1's mixed-signal cycle), each against a closed form: a break list that
re-initialises a quantity at an 'above event (a bouncing ball, a hard stop)."""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from wrsim.cli import main

BALL = """\
-- A ball dropped from h0 bounces on the floor with restitution e: the apex after bounce k is e**(2k) * h0.
library ieee;
use ieee.mechanical_systems.all;
entity ball_tb is
  generic (g : real := 9.81; e : real := 0.8; h0 : displacement := 1.0);
end entity ball_tb;
architecture bounce of ball_tb is
  quantity x : displacement;
  quantity v : velocity;
begin
  break x => h0, v => 0.0;
  break v => -e * v when not x'above(0.0);
  x'dot == v;
  v'dot == -g;
end architecture bounce;
"""


def _waves(tmp_path: Path, name: str, text: str, top: str, stop: str, *args: str) -> dict[str, np.ndarray]:
    """`wrsim run` of one file; its waveforms by column name (the time as "t")."""
    (tmp_path / f"{name}.vhd").write_text(text)
    assert main(["run", str(tmp_path / f"{name}.vhd"), "--top", top, "--stop", stop,
                 "--results", str(tmp_path / "out"), *args]) == 0
    with (tmp_path / "out" / "run" / top / "waveforms.csv").open() as f:
        rows = list(csv.reader(f))
    data = np.array(rows[1:], dtype=float)
    return {"t": data[:, 0], **{name.split("_" + top)[0]: data[:, k] for k, name in enumerate(rows[0]) if k}}


def test_a_bouncing_ball_restarts_its_speed_at_each_impact(tmp_path):
    w = _waves(tmp_path, "ball", BALL, "ball_tb", "3", "--max-step", "1e-4")
    t, x, v = w["t"], w["x"], w["v"]
    g, e = 9.81, 0.8
    t1 = np.sqrt(2.0 / g)
    impacts = t1 + np.concatenate([[0.0], np.cumsum(2.0 * e ** np.arange(1, 5) * g * t1 / g)])
    jumps = t[1:][np.diff(v) > 0.5]            # v jumps from -v to +e*v within the driver's 1 us
    seen = np.array([jumps[np.argmin(np.abs(jumps - ti))] for ti in impacts])
    np.testing.assert_allclose(seen, impacts, rtol=1e-3, atol=2e-3)   # 2 ms: the CSV's sample spacing (1.5 ms)
    for k in range(1, 4):
        apex = x[(t > impacts[k - 1]) & (t < impacts[k])].max()
        assert abs(apex / (e ** (2 * k)) - 1.0) < 1e-2, (k, apex)
    assert x.min() > -1e-4                     # the floor: a 1 us landing at 4.4 m/s
