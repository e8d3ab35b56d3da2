"""Birth and death of prescribed motions and rigid walls (issue 33, item 5; LS-DYNA Keyword User's
Manual, *BOUNDARY_PRESCRIBED_MOTION BIRTH/DEATH: "time imposed motion/constraint is activated /
removed"; *RIGIDWALL BIRTH/DEATH: the wall acts between them).

- A 10 mm one-element plate under 100 g, thrown up at 1 m/s, its z velocity prescribed at 5 m/s
  from 0.2 to 0.6 ms: before the birth it flies freely, z = v0 t - g t^2 / 2; between birth and
  death it moves at 5 m/s; after the death it flies freely again from 5 m/s,
  z = z_d + 5 (t - d) - g (t - d)^2 / 2, which central differences integrate exactly from the
  release's half step (the step is held at 1 us so birth and death fall on steps).
- A 20 mm plate falling at 10 m/s from 5 mm above a 2 mm slab (a box wall): a wall alive from the
  start, or born before the impact, throws it back (the same bits: before the impact it gives no
  force); one born after the plate has passed the slab, or dead before it arrives, lets it through at
  exactly -10 m/s with no wall force.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn.running import launch

STEEL = {"density": 7850.0, "youngs_modulus": 210e9, "poisson_ratio": 0.3}
G, V0, V, BIRTH, DEATH = 1000.0, 1.0, 5.0, 2e-4, 6e-4


def _run(model: paradyn.deck.Model, folder: Path, ranks: int = 1) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    paradyn.deck.write_deck(model, folder / "deck.h5")
    launch.run_engine(folder / "deck.h5", folder / "results.h5", ranks, 1)
    return folder / "results.h5"


def _thrown(**life: float) -> paradyn.deck.Model:
    s = paradyn.Scene("thrown", end_time=1e-3, output_interval=5e-5)
    s.add_material("steel", model="elastic", **STEEL)
    s.add_part("plate", material="steel", thickness=0.001, initial_velocity=[0.0, 0.0, V0],
               geometry=paradyn.Plate((0.01, 0.01), (1, 1)))
    s.add_prescribe("plate", box=[[-1, -1, -1], [1, 1, 1]], dof="uz", value=V, **life)
    model = s.build()
    model.control.gravity_z = -G
    model.control.time_step = 1e-6
    return model


def test_a_motion_acts_between_its_birth_and_its_death(tmp_path: Path) -> None:
    """Free flight under g before the birth, 5 m/s between, free flight from 5 m/s after the death
    (the 4 nodes' displacements to 1e-12 m, velocities to 1e-9 m/s). Central differences release
    the dof from its last half-step velocity V, so after the death z = z_d + V tau - g tau (tau + dt) / 2
    (tau = t - d; the continuous free flight differs by g tau dt / 2, 2e-7 m at the end) and the
    frames' velocity, the half step's after them, is V - g (tau + dt / 2)."""
    dt = 1e-6
    with h5py.File(_run(_thrown(birth_time=BIRTH, death_time=DEATH), tmp_path / "life")) as f:
        t = f["frames/time"][()]
        z = f["frames/displacement"][:, :, 2]
        vz = f["frames/velocity"][:, :, 2]
    z_b = V0 * BIRTH - 0.5 * G * BIRTH**2
    z_d = z_b + V * (DEATH - BIRTH)
    tau = t - DEATH
    z_ref = np.where(t <= BIRTH, V0 * t - 0.5 * G * t**2,
                     np.where(t <= DEATH, z_b + V * (t - BIRTH), z_d + V * tau - 0.5 * G * tau * (tau + dt)))
    np.testing.assert_allclose(z, z_ref[:, None] * np.ones((1, 4)), rtol=0, atol=1e-12)
    during = (t > BIRTH) & (t < DEATH)
    assert np.all(vz[during] == V)
    after = t > DEATH
    np.testing.assert_allclose(vz[after], (V - G * (tau[after] + 0.5 * dt))[:, None] * np.ones((1, 4)),
                               rtol=0, atol=1e-9)
    assert (t <= BIRTH).sum() >= 3 and after.sum() >= 5


def test_a_motion_without_birth_or_death_is_the_same_bits(tmp_path: Path) -> None:
    """birth 0 and death 1e20 written out give the bits of the deck without the datasets."""
    a = _run(_thrown(), tmp_path / "plain")
    b = _run(_thrown(birth_time=0.0, death_time=1e20), tmp_path / "explicit")
    with h5py.File(a) as one, h5py.File(b) as two:
        assert np.array_equal(one["frames/displacement"][()], two["frames/displacement"][()])


def _slab(**life: float) -> paradyn.deck.Model:
    s = paradyn.Scene("slab", end_time=1.5e-3, output_interval=1e-4, history_interval=1e-5)
    s.add_material("steel", model="elastic", **STEEL)
    s.add_part("plate", material="steel", thickness=0.001, initial_velocity=[0.0, 0.0, -10.0],
               geometry=paradyn.Plate((0.02, 0.02), (1, 1), origin=[0.0, 0.0, 0.005]))
    s.add_rigid_wall(point=[-0.1, -0.1, 0.0], normal=[0.0, 0.0, 1.0], shape="box", edge=[1.0, 0.0, 0.0],
                     size=[0.2, 0.2, 0.002], **life)
    return s.build()


def _fall(results: Path) -> tuple[np.ndarray, np.ndarray]:
    with h5py.File(results) as f:
        return f["frames/velocity"][:, :, 2], f["history/rigid_wall_force"][:, 0, 2]


def test_a_wall_acts_between_its_birth_and_its_death(tmp_path: Path) -> None:
    """The plate reaches the slab's face at 0.5 ms and would be through it by 0.7 ms."""
    alive_v, alive_f = _fall(_run(_slab(), tmp_path / "alive"))
    assert alive_v[-1].mean() > 5.0 and alive_f.max() > 0.0
    early_v, early_f = _fall(_run(_slab(birth_time=2e-4), tmp_path / "early"))
    assert np.array_equal(early_v, alive_v) and np.array_equal(early_f, alive_f)
    for name, life in (("late", {"birth_time": 1e-3}), ("dead", {"death_time": 3e-4})):
        v, force = _fall(_run(_slab(**life), tmp_path / name))
        assert np.all(v == -10.0) and np.all(force == 0.0), name


def test_scene_refuses_a_motion_that_dies_before_its_birth() -> None:
    s = paradyn.Scene("bad", end_time=1e-3, output_interval=1e-4)
    s.add_material("steel", model="elastic", **STEEL)
    s.add_part("plate", material="steel", thickness=0.001, geometry=paradyn.Plate((0.01, 0.01), (1, 1)))
    with pytest.raises(paradyn.scene.SceneError, match=r"'death_time' in \[\[prescribe\]\] #1 .* must come after"):
        s.add_prescribe("plate", box=[[-1, -1, -1], [1, 1, 1]], dof="uz", value=1.0, birth_time=2e-4,
                        death_time=1e-4)


def test_keyword_birth_and_death_of_walls_and_motions(tmp_path: Path) -> None:
    """*RIGIDWALL_PLANAR BIRTH 0.001, DEATH 0.002 and *BOUNDARY_PRESCRIBED_MOTION_NODE BIRTH 0.0002,
    DEATH 0.0005 become the rows' birth_time and death_time (the small plate's deck is in s), without
    a warning; a wall's DEATH 0 is never (1e20), and a DEATH before BIRTH is refused."""
    from paradyn.keyword.reader import KeywordError
    from paradyn.keyword.scene import load_keyword
    from test_keyword import HEAD, MESH

    def read(extra: str):
        path = tmp_path / "model.k"
        path.write_text(HEAD + MESH + extra + "*END\n")
        return load_keyword(path)

    wall = ("*RIGIDWALL_PLANAR\n{:>10}{:>10}{:>10}{:>10}{:>10}{:>10}\n"
            "       0.0       0.0      -1.0       0.0       0.0       1.0\n")
    motion = ("*BOUNDARY_PRESCRIBED_MOTION_NODE\n        13         3         0         7       1.0         0"
              "    0.0005    0.0002\n*DEFINE_CURVE\n         7\n                 0.0                 1.0\n"
              "                 1.0                 1.0\n")
    loaded = read(wall.format(0, 0, 0, 0.0, 0.001, 0.002) + motion)
    model = loaded.model
    assert model.rigid_wall_birth_time.tolist() == [0.001] and model.rigid_wall_death_time.tolist() == [0.002]
    assert model.prescribed_birth_time.tolist() == [0.0002] and model.prescribed_death_time.tolist() == [0.0005]
    assert not any("BIRTH" in w or "DEATH" in w for w in loaded.warnings)
    assert read(wall.format(0, 0, 0, 0.0, 0.0, 0.0)).model.rigid_wall_death_time.tolist() == [1e20]
    with pytest.raises(KeywordError, match="give BIRTH >= 0 and a DEATH after it"):
        read(wall.format(0, 0, 0, 0.0, 0.002, 0.001))
