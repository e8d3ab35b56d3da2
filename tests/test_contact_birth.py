"""A contact born later is checked at its birth (issue 33, item 6): LS-DYNA checks a contact with
BT > 0 for initial penetrations when it starts to act, not at t = 0 (Keyword User's Manual,
*CONTACT card 2, BT). The start checks skip it (tests/test_erosion.py: parts that cross at t = 0
and are apart at the birth run); at its birth the same checks run on the positions then, with the
same rules as at the start (docs/theory.md, "Birth and death"):

- mid-surfaces that cross at the birth are refused, as at the start ("cross at its birth");
- slave nodes inside the contact thickness are reported with the start's warning, naming the
  birth, and moved onto the surface ("move", the default): a plate resting 1 mm deep inside the
  2 mm reach of a held floor rises by exactly that depth at the birth and stays at rest (on the
  surface: no force), as the same plate checked at the start does;
- or their overlaps at the birth become their gaps ("gap"): nothing moves, no force, at rest.

Without the check at the birth the penalty would throw the plate off at the birth.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn.running import launch
from paradyn.running.engine_process import EngineError

STEEL = {"density": 7850.0, "youngs_modulus": 210e9, "poisson_ratio": 0.3}
BIRTH = 2e-4          # s
DEPTH = 1e-3          # m: the plate 1 mm above the floor, inside the 2 mm reach (t_a + t_b) / 2


def _run(model: paradyn.deck.Model, folder: Path, ranks: int = 1) -> tuple[Path, str]:
    folder.mkdir(parents=True, exist_ok=True)
    paradyn.deck.write_deck(model, folder / "deck.h5")
    launch.run_engine(folder / "deck.h5", folder / "results.h5", ranks, 1, log_path=folder / "engine.log")
    return folder / "results.h5", (folder / "engine.log").read_text()


def _resting(birth: float, mode: str | None = None, velocity: float = 0.0) -> paradyn.deck.Model:
    """A held 0.1 m floor (4 x 4, 2 mm) and a 15 mm plate (2 mm) 1 mm above it, between the
    floor's nodes (no floor node lies under it), at rest or moving up at `velocity`."""
    s = paradyn.Scene("resting", end_time=5e-4, output_interval=5e-5, history_interval=5e-6)
    s.add_material("steel", model="elastic", **STEEL)
    s.add_part("plate", material="steel", thickness=0.002, initial_velocity=[0.0, 0.0, velocity],
               geometry=paradyn.Plate((0.015, 0.015), (1, 1), origin=[0.03, 0.03, DEPTH]))
    s.add_part("floor", material="steel", thickness=0.002, geometry=paradyn.Plate((0.1, 0.1), (4, 4)))
    s.add_fix("floor", box=[[-1, -1, -1], [1, 1, 1]])
    options = {"birth_time": birth} if birth > 0 else {}
    if mode is not None:
        options["initial_penetration"] = mode
    s.add_contact("plate", "floor", **options)
    return s.build()


def _plate(results: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    with h5py.File(results) as f:
        return (f["frames/time"][()], f["frames/displacement"][:, :4, 2], f["frames/velocity"][:, :4, 2],
                f["history/contact_force"][:, 0, 2])


def test_moved_onto_the_surface_at_its_birth(tmp_path: Path) -> None:
    """Born at 0.2 ms ("move"): the log reports the plate's 4 nodes 1 mm deep at the birth; until
    then the plate rests where it was, from the birth it stands 1 mm higher (the depth, to
    round-off) and stays at rest with no force, as the same contact checked at the start leaves it."""
    results, log = _run(_resting(BIRTH), tmp_path / "born")
    line = next(x for x in log.splitlines() if "initial penetration in /contact/pairs[0]" in x)
    assert "4 nodes of part 0" in line and "deepest 1.000E-03 m" in line
    assert "moved onto the surface at its birth (t = 2.0" in line
    t, dz, vz, force = _plate(results)
    assert np.all(dz[t < BIRTH] == 0.0)
    np.testing.assert_allclose(dz[t >= BIRTH], DEPTH, rtol=0, atol=1e-15)
    assert np.all(vz == 0.0) and np.all(force == 0.0)
    start_results, start_log = _run(_resting(0.0), tmp_path / "start")
    assert "moved onto the surface;" in start_log or "moved onto the surface\n" in start_log + "\n"
    np.testing.assert_allclose(_plate(start_results)[1], DEPTH, rtol=0, atol=1e-15)


def test_overlap_at_its_birth_kept_as_the_gap(tmp_path: Path) -> None:
    """Born at 0.2 ms, "gap": reported as kept, nothing moves, no force: the plate rests."""
    results, log = _run(_resting(BIRTH, "gap"), tmp_path / "gap")
    lines = [x for x in log.splitlines() if "initial penetration in /contact/pairs[0]" in x]
    assert lines and all("kept as the initial gap at its birth" in x for x in lines)
    _, dz, vz, force = _plate(results)
    assert np.all(dz == 0.0) and np.all(vz == 0.0) and np.all(force == 0.0)


def test_parts_that_cross_at_its_birth_are_refused(tmp_path: Path) -> None:
    """A blade at rest through the floor's middle, with the contact born at 0.2 ms: the start runs
    (the start checks skip it), the birth refuses the run with the start's message, naming the birth."""
    s = paradyn.Scene("blade", end_time=5e-4, output_interval=1e-4)
    s.add_material("steel", model="elastic", **STEEL)
    s.add_part("floor", material="steel", thickness=0.002, geometry=paradyn.Plate((0.1, 0.1), (4, 4)))
    s.add_fix("floor", box=[[-1, -1, -1], [1, 1, 1]])
    s.add_part("blade", material="steel", thickness=0.002,
               geometry=paradyn.Plate((0.02, 0.01), (2, 1), origin=[0.035, 0.0375, -0.005],
                                      u_axis=[1, 0, 0], v_axis=[0, 0, 1]))
    s.add_contact("blade", "floor", birth_time=BIRTH)
    with pytest.raises(EngineError, match=r"cross at its birth \(t = +2\.0\d*E-04 s\)"):
        _run(s.build(), tmp_path / "blade")


@pytest.mark.mpi
@pytest.mark.parametrize("mode", ["move", "gap"])
def test_two_ranks_give_the_one_rank_birth_bitwise(tmp_path: Path, mode: str) -> None:
    """The birth's move and gap on 2 ranks (local contact) give the one-rank frames bit for bit."""
    one, _ = _run(_resting(BIRTH, mode), tmp_path / "one")
    two, _ = _run(_resting(BIRTH, mode), tmp_path / "two", 2)
    with h5py.File(one) as a, h5py.File(two) as b:
        for key in ("frames/displacement", "frames/velocity", "history/contact_force"):
            assert np.array_equal(a[key][()], b[key][()]), key
