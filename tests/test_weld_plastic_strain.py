"""Weld failure by plastic strain (docs/theory.md, "Weld failure by plastic strain"): a spot weld
(LS-DYNA *CONSTRAINED_SPOTWELD EP) lets its nodes go when the effective plastic strain of the
shells around its nodes reaches EP (a ParaDyn weld is rigid and has no strain of its own).

Two strips 20 x 5 x 2 mm (4 x 1 shells) of a bilinear elastic-plastic steel (*MAT_PLASTIC_KINEMATIC:
E = 200 GPa, SIGY = 200 MPa, ETAN = 2 GPa) end to end across a 1 mm gap, joined by two welds at the
corners of their facing ends; the first strip held at x = 0 (free to contract across), the far
end of the second pulled at v(t) = V min(t / t_r, 1). In uniaxial tension both strips strain alike,
e = d / 2L with the pulled end's displacement d (the weld is rigid), and with the hardening
modulus H = E ETAN / (E - ETAN) the plastic strain is e_p = (e - SIGY / E) / (1 + H / E). The welds
fail when e_p = EP:

    t_f = 2L (SIGY / E + EP (1 + H / E)) / V + t_r / 2.

The ramp t_r = 0.1 ms spans a dozen wave transits (quasi-static to a few per mille: measured +0.5 %
and +0.7 %). Failing on the total strain instead would come 16 % (EP 0.005) and 9 % (EP 0.01) early.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn.keyword.scene import load_keyword
from paradyn.running import launch

LENGTH = 0.02    # m, each strip
WIDTH = 0.005    # m
E, SIGY, ETAN = 2.0e11, 2.0e8, 2.0e9
SPEED = 0.5      # m/s, the pulled end's speed after the ramp
RAMP = 1.0e-4    # s
END = 1.2e-3     # s


def _deck(ep: float) -> str:
    nodes: list[tuple[float, float, float]] = []
    for x0 in (0.0, LENGTH + 0.001):
        nodes += [(x0 + i * LENGTH / 4, j * WIDTH, 0.0) for i in range(5) for j in range(2)]
    shells = [(10 * strip + 2 * i + 1, 10 * strip + 2 * i + 3, 10 * strip + 2 * i + 4, 10 * strip + 2 * i + 2)
              for strip in range(2) for i in range(4)]
    text = ("*KEYWORD\n*CONTROL_TERMINATION\n" + f"{END:10.6f}\n" +
            f"*MAT_PLASTIC_KINEMATIC\n         1    7800.0{E:10.3e}       0.3{SIGY:10.3e}{ETAN:10.3e}       0.0\n"
            "       0.0       0.0       0.0\n"
            "*SECTION_SHELL\n         1         2                   3\n     0.002     0.002     0.002     0.002\n"
            "*PART\nheld\n         1         1         1\n*PART\npulled\n         2         1         1\n*NODE\n")
    text += "".join(f"{k + 1:8d}{x:16.6f}{y:16.6f}{z:16.6f}\n" for k, (x, y, z) in enumerate(nodes))
    text += "*ELEMENT_SHELL\n" + "".join(f"{k + 1:8d}{1 + k // 4:8d}" + "".join(f"{n:8d}" for n in shell) + "\n"
                                        for k, shell in enumerate(shells))
    # node 1 held in every dof, node 2 (across the width) free in y: the strip contracts freely
    text += ("*BOUNDARY_SPC_NODE\n         1         0         1         1         1         1         1         1\n"
             "         2         0         1         0         1         1         1         1\n")
    text += (f"*DEFINE_CURVE\n         1\n                 0.0             0.0\n{RAMP:20.6e}             1.0\n"
             "                 1.0             1.0\n*BOUNDARY_PRESCRIBED_MOTION_NODE\n")
    text += "".join(f"{n:10d}         1         0         1{SPEED:10.4f}\n" for n in (19, 20))
    text += "*CONSTRAINED_SPOTWELD\n"
    text += "".join(f"{a:10d}{b:10d}       0.0       0.0       0.0       0.0     1e+20{ep:10.4f}\n"
                    for a, b in ((9, 11), (10, 12)))
    return text + "*END\n"


def _run(tmp_path: Path, ep: float, ranks: int = 1) -> Path:
    path = tmp_path / "strips.k"
    path.write_text(_deck(ep))
    model = load_keyword(path).model
    model.control.history_interval = 2e-6
    folder = tmp_path / f"ranks{ranks}"
    folder.mkdir()
    paradyn.deck.write_deck(model, folder / "deck.h5")
    launch.run_engine(folder / "deck.h5", folder / "results.h5", ranks, 1)
    return folder / "results.h5"


def _failure_time(results: Path) -> tuple[float, np.ndarray]:
    with h5py.File(results) as f:
        t = f["history/time"][:]
        failed = f["history/failed_welds"][:]
    first = int(np.argmax(failed > 0))
    assert failed[first] > 0, "no weld failed"
    return float(t[first]), failed


@pytest.mark.parametrize("ep", [0.005, 0.01])
def test_a_weld_lets_go_when_its_shells_reach_ep(tmp_path: Path, ep: float) -> None:
    hardening = E * ETAN / (E - ETAN)
    expected = 2.0 * LENGTH * (SIGY / E + ep * (1.0 + hardening / E)) / SPEED + 0.5 * RAMP
    time, failed = _failure_time(_run(tmp_path, ep))
    assert abs(time - expected) < 0.02 * expected, (time, expected)
    assert failed[-1] == 2.0


def test_the_weld_keyword_reads_ep(tmp_path: Path) -> None:
    path = tmp_path / "strips.k"
    path.write_text(_deck(0.01))
    read = load_keyword(path)
    np.testing.assert_allclose(read.model.rigid_body_failure_plastic_strain, [0.01, 0.01])
    assert not any("plastic strain" in w for w in read.warnings)


@pytest.mark.mpi
def test_weld_strain_failure_is_bitwise_the_same_on_two_ranks(tmp_path: Path) -> None:
    if shutil.which("mpirun") is None and shutil.which("mpiexec") is None:
        pytest.skip("mpirun is not installed")
    one, two = _run(tmp_path, 0.01), _run(tmp_path, 0.01, ranks=2)
    with h5py.File(one) as a, h5py.File(two) as b:
        for key in ("history/failed_welds", "frames/displacement"):
            assert np.array_equal(a[key][:], b[key][:]), key
