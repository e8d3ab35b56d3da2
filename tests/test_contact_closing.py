"""The automatic contact step limit (``[run] contact_closing_limit``, default 0.05; issue 35 item 3;
docs/theory.md, Contact, and docs/contact-edges.md): a slave near its master surface may close on it
by at most the fraction f of the thinner shell wall in one step, so the step is cut to
f t / v_closing while the pair is near, and it grows back by at most 5 % a cycle after.

The plates of tests/test_contact_travel.py: two free 6 x 6 plates 0.1 m square, walls t = 0.1 mm,
0.1 mm apart, closing at 2 x 20 m/s. At the automatic step (about 3 us) a node moves 0.6 t a step
and the plates pass through each other (that file). By default the pairs are near from the first
step (0.1 mm apart, less than twice 40 m/s times the step) and their relative speed is 40 m/s, so
the step is 0.05 t / (40 m/s) = 0.125 us exactly (history dt_element = -3: the closing limit sets
it), and the plates stop on each other with the penalty's own penetration, the node-pair
oscillator's 2 v / omega (tests/test_contact_impact.py), as with the travel limit.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import models as M
from contact_cases import STEEL
from paradyn.deck import Control
from paradyn.mesh import geometry

T = 1.0e-4
V = 20.0
FRACTION = 0.05   # the default (schema/control.toml contact_closing_limit)


def _run(tmp_path: Path, gap: float = 1.0e-4, speed: float = V, end_time: float = 3.0e-5,
         history_interval: float = 2.5e-7, **control: float):
    a = M.flat_plate((0.1, 0.1), (6, 6), origin=(0.0, 0.0, -0.5 * (T + gap)))
    b = geometry.Mesh(coordinates=a.coordinates * np.array([1.0, 1.0, -1.0]), quads=a.quads[:, ::-1].copy())
    settings = Control(end_time=end_time, output_interval=end_time / 3, history_interval=history_interval, **control)
    asm = M.contact_model([M.Body(a, T, (0, 0, speed)), M.Body(b, T, (0, 0, -speed))], STEEL, settings,
                          tracked=[24, a.n_nodes + 24])
    return M.run(asm.model, tmp_path).results.history


def test_the_default_limit_sets_the_step_and_stops_the_plates(tmp_path: Path) -> None:
    assert Control(end_time=1.0, output_interval=1.0).contact_closing_limit == FRACTION
    h = _run(tmp_path)
    assert h["dt_element"][0] == -3
    assert h["dt"][0] == pytest.approx(FRACTION * T / (2.0 * V), rel=1e-9)
    mesh = M.flat_plate((0.1, 0.1), (6, 6))
    omega = 2.0 * np.sqrt(M.segment_stiffness(mesh, STEEL, 0.1)[0] / (STEEL.density * T * (0.1 / 6) ** 2))
    assert h["contact_penetration"].max() == pytest.approx(2.0 * V / omega, rel=0.05)
    z = h["tracked_displacement"][:, :, 2]
    assert np.all(z[:, 0] - z[:, 1] < 1.0e-4 + T)     # the mid-surfaces never cross


def test_switched_off_the_plates_pass_through(tmp_path: Path) -> None:
    h = _run(tmp_path, contact_closing_limit=0.0)
    assert np.all(h["dt_element"] >= 0)
    z = h["tracked_displacement"][:, :, 2]
    assert np.any(z[:, 0] - z[:, 1] > 1.0e-4 + T)


def test_the_step_grows_back_by_at_most_five_percent_a_cycle(tmp_path: Path) -> None:
    """A record every cycle (history interval below the step): wherever the closing limit set the
    step, the next step is at most 1.05 times it; the plates rebound and part, and the step
    returns to the elements' own."""
    h = _run(tmp_path, end_time=2.0e-4, history_interval=1.0e-9)
    dt, ctl = h["dt"], h["dt_element"]
    limited = np.flatnonzero(ctl[:-1] == -3)
    assert limited.size > 50
    assert np.all(dt[limited + 1] <= 1.05 * dt[limited] * (1.0 + 1e-12))
    assert ctl[-1] >= 0 and dt[-1] > 10 * dt[0]        # apart again: the elements' step


def test_a_pair_that_is_far_or_slow_pays_nothing(tmp_path: Path) -> None:
    """Plates 10 mm apart closing at 2 x 0.5 m/s for 20 us: never near, so the run is bitwise
    the run without the limit."""
    on = _run(tmp_path / "on", gap=1.0e-2, speed=0.5, end_time=2.0e-5)
    off = _run(tmp_path / "off", gap=1.0e-2, speed=0.5, end_time=2.0e-5, contact_closing_limit=0.0)
    assert np.all(on["dt_element"] >= 0)
    for name in ("dt", "kinetic_energy", "internal_energy", "tracked_displacement"):
        assert np.array_equal(on[name], off[name]), name


def test_a_fraction_of_one_or_more_is_refused(tmp_path: Path) -> None:
    from paradyn.scene import SceneError, load_scene
    case = Path(__file__).resolve().parents[1] / "cases" / "pipe_whip" / "scene.toml"
    path = tmp_path / "scene.toml"
    path.write_text(case.read_text().replace("[run]\n", "[run]\ncontact_closing_limit = 1.5\n", 1))
    with pytest.raises(SceneError, match=r"contact_closing_limit.*must be in \[0, 1\)"):
        load_scene(path)
