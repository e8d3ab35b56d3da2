"""The contact thickness scale (``[[contact]] thickness_scale``, /contact/thickness_scale; LS-DYNA's
SFST and SFMT on card 3 of *CONTACT_...; docs/theory.md, "Contact thickness").

A contact surface sits s t / 2 off each side of its shell's mid-surface, so a slave node of the
first part (thickness t1, scale s1) comes to rest on a segment of the second (t2, s2) at the
mid-surface distance

    d = (s1 t1 + s2 t2) / 2 - m g / k,

the contact distance less the static penalty compression of a node of mass m under gravity g on the
segment's spring k = scale K A / longest diagonal (K = E / (3 (1 - 2 nu)), docs/formats.md). A
single 5 cm element of 1 mm steel settles under gravity (mass damping) on one held 20 cm element of
2 mm steel, whose corners lie outside the small plate (so only the small plate's nodes are slaves
that touch). The penalty scale is small enough (2e-8) that m g / k is 6 to 7 % of d: both terms
are checked (to 1e-6; the rest distance matches to 3e-9), and so is which scale goes with which
part (swapped, d would be 1.25 mm, not 1.75 mm).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import paradyn
from paradyn.keyword.scene import load_keyword
from paradyn.scene import SceneError
from paradyn.studies.design import KNOBS
from test_keyword import HEAD, TWO_PARTS, _deck

E, NU, RHO = 200.0e9, 0.3, 7850.0
T_SMALL, T_BASE = 1.0e-3, 2.0e-3
SMALL, BASE = 0.05, 0.2
G = 9.81
PENALTY = 2.0e-8


def _rest_distance(scales: tuple[float, float]) -> float:
    """The analytic mid-surface distance at rest: (s1 t1 + s2 t2) / 2 - m g / k."""
    m = RHO * T_SMALL * SMALL**2 / 4.0                       # one of the small plate's four nodes
    k = PENALTY * E / (3.0 * (1.0 - 2.0 * NU)) * BASE**2 / (BASE * np.sqrt(2.0))
    return 0.5 * (scales[0] * T_SMALL + scales[1] * T_BASE) - m * G / k


def _settle(tmp_path: Path, scales: tuple[float, float] | None) -> float:
    """The small plate's corner height above the base's mid-surface after settling."""
    s1, s2 = scales or (1.0, 1.0)
    start = 0.5 * (s1 * T_SMALL + s2 * T_BASE) + 1.0e-4    # dropped from 0.1 mm above the contact distance
    scene = paradyn.Scene("contact thickness", end_time=0.12, output_interval=0.04, history_interval=1.0e-3,
                          gravity=[0.0, 0.0, -G], mass_damping=300.0)
    scene.add_material("steel", model="elastic", density=RHO, youngs_modulus=E, poisson_ratio=NU)
    corner = 0.5 * (BASE - SMALL)
    scene.add_part("small", material="steel", thickness=T_SMALL,
                   geometry=paradyn.Plate(size=(SMALL, SMALL), elements=(1, 1), origin=(corner, corner, start)))
    scene.add_part("base", material="steel", thickness=T_BASE,
                   geometry=paradyn.Plate(size=(BASE, BASE), elements=(1, 1)))
    scene.add_fix("base", box=[[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]])
    scene.add_track("corner", part="small", point=[corner, corner, start])
    options = {} if scales is None else {"thickness_scale": list(scales)}
    scene.add_contact("small", "base", penalty_scale=PENALTY, **options)
    res = paradyn.run(scene, tmp_path, ranks=1, threads=1, post=False)
    dz = res.history["tracked_displacement"][:, 0, 2]
    assert np.ptp(dz[-20:]) < 1e-3 * _rest_distance(scales or (1.0, 1.0))   # at rest
    return start + float(dz[-1])


@pytest.mark.parametrize("scales", [None, (0.5, 1.5)], ids=["default", "sfst-0.5-sfmt-1.5"])
def test_a_plate_comes_to_rest_at_the_scaled_contact_distance(tmp_path: Path, scales) -> None:
    expected = _rest_distance(scales or (1.0, 1.0))
    assert _settle(tmp_path, scales) == pytest.approx(expected, rel=1e-6)   # measured: 3e-9


def test_one_number_scales_both_parts_and_a_pair_each() -> None:
    scene = paradyn.Scene("s", end_time=1e-4, output_interval=1e-4)
    scene.add_material("steel", model="elastic", density=RHO, youngs_modulus=E, poisson_ratio=NU)
    for name, z in (("a", 0.0), ("b", 0.01)):
        scene.add_part(name, material="steel", thickness=1e-3,
                       geometry=paradyn.Plate(size=(0.1, 0.1), elements=(2, 2), origin=(0.0, 0.0, z)))
    scene.add_contact("a", "b", thickness_scale=0.5)
    scene.add_contact("b", "a", thickness_scale=[0.25, 2.0])
    scene.add_contact("b", "a")
    model = scene.build()
    assert model.contact_thickness_scale.tolist() == [[0.5, 0.5], [0.25, 2.0], [1.0, 1.0]]
    with pytest.raises(SceneError, match="thickness_scale"):
        scene.add_contact("a", "b", thickness_scale=0.0)
    with pytest.raises(SceneError, match="thickness_scale"):
        scene.add_contact("a", "b", thickness_scale=[1.0, 1.0, 1.0])
    with pytest.raises(SceneError, match="one number"):
        scene.add_contact(kind="single_surface", thickness_scale=[0.5, 1.0])


def test_the_study_knob_sets_every_contact() -> None:
    scene = paradyn.scene.load_scene(Path(__file__).resolve().parents[1] / "cases" / "pipe_whip" / "scene.toml")
    knob = KNOBS["contact_thickness_scale"]
    assert knob.base(scene) == 1.0
    knob.apply(scene, 0.5)
    assert [c.thickness_scale for c in scene.contacts] == [(0.5, 0.5)] * len(scene.contacts)
    assert knob.base(scene) == 0.5


@pytest.mark.parametrize(("card3", "single", "expected"), [
    ("       1.0       1.0       0.0       0.0       0.5       1.5\n", False, [[0.5, 1.5]]),
    ("       1.0       1.0       0.0       0.0       0.0       0.0\n", False, [[1.0, 1.0]]),
    ("\n", False, [[1.0, 1.0]]),
    ("       1.0       1.0       0.0       0.0      0.75       2.0\n", True, [[0.75, 0.75]] * 3),
], ids=["sfst-sfmt", "zero-is-default", "blank", "single-surface-takes-sfst"])
def test_keyword_sfst_sfmt_read_as_the_thickness_scale(tmp_path: Path, card3: str, single: bool, expected) -> None:
    """SFST (slave side: the pair's first part) and SFMT (master side) on card 3; 0 or blank is
    LS-DYNA's default 1; a single-surface contact has one surface and takes SFST on every row."""
    if single:
        body = "*CONTACT_AUTOMATIC_SINGLE_SURFACE\n         0         0         5\n       0.3\n" + card3
    else:
        body = "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n         1         2         3         3\n       0.3\n" + card3
    read = load_keyword(_deck(tmp_path, HEAD + TWO_PARTS + body))
    assert read.model.contact_thickness_scale.tolist() == expected
    assert not [w for w in read.warnings if "SFST" in w or "SFMT" in w]
