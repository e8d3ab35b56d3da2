"""Keyword loads and motions on ParaDyn's effects (issue 33, item 2; docs/keyword.md, "Loads and
motions"): *LOAD_NODE_POINT / _SET as sums of ramps, *BOUNDARY_PRESCRIBED_MOTION (VAD 0, 1, 2) as
velocity curves, *INITIAL_VELOCITY with sets and a *DEFINE_BOX, *DEFINE_CURVE's options; each deck
is the small plate of tests/test_keyword.py with cards added, its model checked value by value; one
run checks that a keyword point load moves a free plate as Newton says."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import paradyn
from paradyn.keyword.curves import JUMP_WIDTH, ramps_of
from paradyn.keyword.reader import KeywordError
from paradyn.keyword.scene import load_keyword
from test_keyword import HEAD, MESH

CURVE = "*DEFINE_CURVE\n{:>10}{:>10}{:>10}{:>10}{:>10}{:>10}\n"


def _curve(lcid: int, points: list[tuple[float, float]], sfa: float = 0.0, sfo: float = 0.0, offa: float = 0.0,
           offo: float = 0.0) -> str:
    head = CURVE.format(lcid, 0, sfa, sfo, offa, offo)
    return head + "".join(f"{a:>20}{o:>20}\n" for a, o in points)


def _read(tmp_path: Path, extra: str, head: str = HEAD, mesh: str = MESH):
    path = tmp_path / "model.k"
    path.write_text(head + mesh + extra + "*END\n")
    return load_keyword(path)


def test_ramps_rebuild_a_piecewise_linear_curve_exactly() -> None:
    """The ramps of a curve with a jump at 0, rises, falls and a flat end add up to the curve."""
    times = np.array([0.0, 0.1, 0.25, 0.4, 1.0])
    values = np.array([2.0, 5.0, -1.0, 3.0, 3.0])
    rows = ramps_of(times, values)
    t = np.linspace(0.0, 1.5, 3001)
    total = sum(value * np.minimum(1.0, t / ramp) if ramp > 0.0 else value + 0.0 * t for ramp, value in rows)
    np.testing.assert_allclose(total, np.interp(t, times, values), rtol=0.0, atol=1e-12)
    assert len(rows) == 4    # the value at once and one ramp per change of slope (none at the flat end)


def test_load_node_point_and_set_are_ramps_of_sf_times_the_curve(tmp_path: Path) -> None:
    """*LOAD_NODE_POINT DOF 3 with SF 2 on a curve rising to 1 at 0.5 ms and flat after: one ramp
    of 2 N over 0.5 ms; DOF 6 (moment about y) is ParaDyn's dof 5; *LOAD_NODE_SET on a constant
    curve: the value at once on each node of the set."""
    extra = ("*LOAD_NODE_POINT\n        13         3         7       2.0\n        16         6         8      -3.0\n"
             "*LOAD_NODE_SET\n         4         1         8       5.0\n"
             "*SET_NODE_LIST\n         4\n        14        15\n"
             + _curve(7, [(0.0, 0.0), (0.0005, 1.0), (0.001, 1.0)]) + _curve(8, [(0.0, 1.0), (0.001, 1.0)]))
    model = _read(tmp_path, extra).model
    assert model.load_node.tolist() == [2, 5, 3, 4]
    assert model.load_dof.tolist() == [3, 5, 1, 1]
    assert model.load_value.tolist() == [pytest.approx(2.0, rel=1e-15), -3.0, 5.0, 5.0]
    assert model.load_ramp_time.tolist() == [0.0005, 0.0, 0.0, 0.0]


def test_point_loads_refuse_followers_and_local_systems(tmp_path: Path) -> None:
    curve = _curve(8, [(0.0, 1.0), (0.001, 1.0)])
    with pytest.raises(KeywordError, match=r"DOF = 4 \(a follower force\) is not read; give DOF 1, 2, 3"):
        _read(tmp_path, "*LOAD_NODE_POINT\n        13         4         8\n" + curve)
    with pytest.raises(KeywordError, match="CID = 2: local coordinate systems are not read"):
        _read(tmp_path, "*LOAD_NODE_POINT\n        13         1         8       1.0         2\n" + curve)
    with pytest.raises(KeywordError, match="LCID = 9 names no"):
        _read(tmp_path, "*LOAD_NODE_POINT\n        13         1         9\n" + curve)


def test_prescribed_displacement_is_its_slope_as_a_velocity(tmp_path: Path) -> None:
    """VAD 2: a displacement rising 2 mm in 0.4 ms, then held, is 5 m/s then 0, the jump a
    transition centred on 0.4 ms so that the velocity's integral is the displacement (2 mm)."""
    extra = ("*BOUNDARY_PRESCRIBED_MOTION_NODE\n        13         3         2         7\n"
             + _curve(7, [(0.0, 0.0), (0.0004, 0.002), (0.001, 0.002)]))
    model = _read(tmp_path, extra).model
    half = JUMP_WIDTH * 0.0004
    assert model.prescribed_node.tolist() == [2] and model.prescribed_dof.tolist() == [3]
    assert model.prescribed_value.tolist() == [1.0] and model.prescribed_curve.tolist() == [0]
    np.testing.assert_allclose(model.curve_time, [0.0, 0.0004 - half, 0.0004 + half, 0.001], rtol=1e-15)
    np.testing.assert_allclose(model.curve_value, [5.0, 5.0, 0.0, 0.0], rtol=1e-12)
    assert np.trapezoid(model.curve_value, model.curve_time) == pytest.approx(0.002, rel=1e-12)


def test_prescribed_acceleration_is_integrated_and_death_releases_the_dof(tmp_path: Path) -> None:
    """VAD 1: 100 m/s^2 from 0 is the velocity 100 t (0.1 m/s at 1 ms); VAD 0 with DEATH 0.5 ms:
    the curve is kept whole and the motion's death_time is 0.5 ms (the engine frees the dof then:
    tests/test_motion_life.py), the default DEATH 1e28 is never (1e20), BIRTH 0; SF scales the
    velocity; a dof prescribed twice is an error."""
    extra = ("*BOUNDARY_PRESCRIBED_MOTION_NODE\n        13         1         1         7\n"
             "*BOUNDARY_PRESCRIBED_MOTION_SET\n         4         2         0         8       0.5            0.0005\n"
             "*SET_NODE_LIST\n         4\n        14        15\n"
             + _curve(7, [(0.0, 100.0), (0.001, 100.0)]) + _curve(8, [(0.0, 0.0), (0.001, 4.0)]))
    read = _read(tmp_path, extra)
    model = read.model
    assert model.prescribed_node.tolist() == [2, 3, 4] and model.prescribed_dof.tolist() == [1, 2, 2]
    assert model.prescribed_value.tolist() == [1.0, 0.5, 0.5] and model.prescribed_curve.tolist() == [0, 1, 1]
    second = int(model.curve_first_point[1])
    np.testing.assert_allclose(model.curve_time[:second], [0.0, 0.001])
    np.testing.assert_allclose(model.curve_value[:second], [0.0, 0.1], rtol=1e-12)
    np.testing.assert_allclose(model.curve_time[second:], [0.0, 0.001])
    np.testing.assert_allclose(model.curve_value[second:], [0.0, 4.0])
    assert model.prescribed_death_time.tolist() == [1e20, 0.0005, 0.0005]
    assert model.prescribed_birth_time.tolist() == [0.0, 0.0, 0.0]
    assert not any("DEATH" in w or "BIRTH" in w for w in read.warnings)
    with pytest.raises(KeywordError, match="prescribes node 13 DOF 1 again"):
        _read(tmp_path, extra + "*BOUNDARY_PRESCRIBED_MOTION_NODE\n        13         1         0         8\n")


def test_initial_velocity_by_box_with_exempted_nodes(tmp_path: Path) -> None:
    """*INITIAL_VELOCITY over every node (NSID 0) in box 5 (x from 0.9 to 2.0, bounds included):
    nodes 12, 13, 15, 16; node set 6 (node 16) is exempted and takes card 3's velocity; node 12 is
    fixed by its TC/RC and keeps 0. IRIGID is warned and ignored."""
    extra = ("*INITIAL_VELOCITY\n         0         6         5         1\n       0.0      -2.0       0.0       0.0"
             "       0.0       3.0\n       7.0\n"
             "*DEFINE_BOX\n         5       0.9       2.0      -1.0       1.0      -1.0       1.0\n"
             "*SET_NODE_LIST\n         6\n        16\n")
    read = _read(tmp_path, extra)
    v, w = read.model.initial_velocity, read.model.initial_angular_velocity
    assert v.tolist() == [[0, 0, 0], [0, 0, 0], [0, -2, 0], [0, 0, 0], [0, -2, 0], [7, 0, 0]]
    assert w[:, 2].tolist() == [0, 0, 3, 0, 3, 0]
    assert any("IRIGID = 1 is ignored" in m for m in read.warnings)
    with pytest.raises(KeywordError, match="BOXID = 9 names no"):
        _read(tmp_path, "*INITIAL_VELOCITY\n         0         0         9\n       1.0\n")


def test_define_curve_scales_offsets_and_extrapolation(tmp_path: Path) -> None:
    """Time A SFA + OFFA, value O SFO + OFFO (SFA, SFO 0.0 mean 1); a positive OFFA holds 0 up to
    0.999 OFFA; a curve ending before the end time goes on to it by its last slope."""
    extra = "*LOAD_BODY_Z\n         7\n" + _curve(7, [(0.0, 1.0), (0.5, 2.0)], 0.001, 0.0, 0.0001, 0.5)
    model = _read(tmp_path, extra).model
    np.testing.assert_allclose(model.curve_time, [0.0, 0.0000999, 0.0001, 0.0006, 0.001], rtol=1e-12)
    np.testing.assert_allclose(model.curve_value, [0.0, 0.0, 1.5, 2.5, 2.5 + 2.0 * 0.4], rtol=1e-12)


FREE_MESH = MESH.replace("       7       7", "")


def test_a_keyword_point_load_moves_a_free_plate_as_newton_says(tmp_path: Path) -> None:
    """A free plate (no constraint) of mass M pulled along x at one node by a force rising to F in
    T/2 and held to T (20 ms, about 200 steps) moves its centre of mass by x(T) = 7 F T^2 / (24 M),
    with momentum 3 F T / 4; in mm-kg-ms (F in kN). A load held at F from the start would give 12/24,
    one reaching F only at T 4/24."""
    head = (HEAD.replace("*CONTROL_TERMINATION\n     0.001", "*CONTROL_UNITS\n        mm        ms        kg\n"
                                                          "*CONTROL_TERMINATION\n      20.0")
            .replace("    7800.0     2e+11", "    7.8e-6     200.0").replace("     0.002" * 4, "       2.0" * 4))
    mesh = (FREE_MESH.replace("             1.0 ", "          1000.0 ")
            .replace("             2.0 ", "          2000.0 ").replace("             0.5 ", "           500.0 "))
    extra = ("*LOAD_NODE_POINT\n        13         1         7       0.5\n"
             + _curve(7, [(0.0, 0.0), (10.0, 1.0), (20.0, 1.0)]))
    model = _read(tmp_path, extra, head=head, mesh=mesh).model
    res = paradyn.run(model, tmp_path / "run", ranks=1, threads=1, post=False)
    area = 0.5 * 1.0    # each element, m^2
    mass = np.zeros(model.n_nodes)
    for quad in model.connectivity:
        mass[quad] += 7800.0 * area * 0.002 / 4.0
    force, end = 500.0, 0.02
    centre = float(mass @ res.displacement[-1][:, 0]) / mass.sum()
    assert res.frame_times[-1] == pytest.approx(end)
    assert centre == pytest.approx(7.0 * force * end**2 / (24.0 * mass.sum()), rel=0.005)
    assert float(mass @ res.velocity[-1][:, 0]) == pytest.approx(0.75 * force * end, rel=0.005)
