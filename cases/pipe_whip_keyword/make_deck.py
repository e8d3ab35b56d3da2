"""Write cases/pipe_whip_keyword/pipe_whip.k: the pipe whip of cases/pipe_whip/scene.toml as an
LS-DYNA keyword deck (docs/keyword.md).

    .venv/bin/python cases/pipe_whip_keyword/make_deck.py [--out PATH]

The mesh is the scene's own (paradyn.scene.build_model): nodes and elements in the model's order,
with ids that are not the row numbers (part p's nodes and elements numbered from 100000 p + 1) so
that reading the deck has to map them. Coordinates are written in free format (commas) with every
digit Python keeps, so the deck's model is the scene's bit for bit; the other cards are in the
standard fixed 10-character columns. The settings that LS-DYNA spells differently:

- the scene's fixed step 1e-6 s is the cap of *CONTROL_TIMESTEP LCTM, a constant *DEFINE_CURVE;
- hourglass form "stiffness" with coefficient 0.1 is *HOURGLASS IHQ 4, QM 0.1;
- no warping correction is ELFORM 2 (Belytschko-Tsay; ELFORM 10 would add it);
- the contact pair is *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE between the two parts, SFS 1 with
  the default SLSFAC 0.1 (the scene's penalty_scale 0.1);
- the fixed end rings are a *SET_NODE_LIST held by *BOUNDARY_SPC_SET; the tracked points are
  *DATABASE_HISTORY_NODE_ID with the scene's names.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from paradyn import deck, scene

HERE = Path(__file__).resolve().parent
SCENE = HERE.parent / "pipe_whip" / "scene.toml"
ID_STRIDE = 100000


def _row(*values: object) -> str:
    return "".join(f"{v:>10}" for v in values)


def _ids(model: deck.Model) -> tuple[np.ndarray, np.ndarray]:
    """Node and element ids: part p's from ID_STRIDE * (p + 1) + 1 on (a node takes its first element's part)."""
    element_ids = np.empty(model.n_elements, dtype=np.int64)
    node_part = np.full(model.n_nodes, -1)
    for part in range(model.n_parts):
        elements = np.flatnonzero(model.element_part == part)
        element_ids[elements] = ID_STRIDE * (part + 1) + 1 + np.arange(elements.size)
        nodes = np.unique(model.connectivity[elements])
        node_part[nodes[node_part[nodes] < 0]] = part
    node_ids = np.empty(model.n_nodes, dtype=np.int64)
    for part in range(model.n_parts):
        nodes = np.flatnonzero(node_part == part)
        node_ids[nodes] = ID_STRIDE * (part + 1) + 1 + np.arange(nodes.size)
    return node_ids, element_ids


def deck_text(sc: scene.Scene, model: deck.Model) -> list[str]:
    node_ids, element_ids = _ids(model)
    run, steel = sc.run, sc.materials[0]
    lines = ["*KEYWORD", "*TITLE", sc.title, "*CONTROL_UNITS", _row("m", "sec", "kg"),
             "*CONTROL_TERMINATION", _row(run.end_time),
             "*CONTROL_TIMESTEP", "$    DTINIT    TSSFAC      ISDO    TSLIMT     DT2MS      LCTM",
             _row(0.0, run.time_step_safety, 0, 0.0, 0.0, 1),
             "*DEFINE_CURVE", _row(1), f"{0.0:>20}{run.time_step:>20}", f"{1.0:>20}{run.time_step:>20}",
             "*DATABASE_BINARY_D3PLOT", _row(run.output_interval),
             "*DATABASE_GLSTAT", _row(run.history_interval),
             "*MAT_PLASTIC_KINEMATIC_TITLE", steel.name,
             "$       MID        RO         E        PR      SIGY      ETAN      BETA",
             _row(1, steel.density, f"{steel.youngs_modulus:.4g}", steel.poisson_ratio, f"{steel.yield_stress:.4g}",
                  steel.tangent_modulus, steel.hardening_mixing)]
    for index, part in enumerate(sc.parts):
        pid = index + 1
        lines += ["*SECTION_SHELL", "$     SECID    ELFORM      SHRF       NIP",
                  _row(pid, 10 if part.warping_correction else 2, 1.0, part.integration_points),
                  _row(*[part.thickness] * 4),
                  "*HOURGLASS",
                  _row(pid, {"viscous": 1, "stiffness": 4}[part.hourglass_form], part.hourglass_coefficient),
                  "*PART", part.name, _row(pid, pid, 1, 0, pid)]
    lines += ["*NODE", "$ free format: every digit of the scene's coordinates"]
    lines += [f"{nid},{x!r},{y!r},{z!r}" for nid, (x, y, z) in zip(node_ids.tolist(), model.coordinates.tolist(),
                                                                  strict=True)]
    lines += ["*ELEMENT_SHELL"]
    lines += ["".join(f"{v:>8}" for v in (eid, part + 1, *node_ids[quad].tolist()))
              for eid, part, quad in zip(element_ids.tolist(), model.element_part.tolist(), model.connectivity,
                                         strict=True)]
    moving = [i + 1 for i, p in enumerate(sc.parts) if any(p.initial_velocity)]
    for pid in moving:
        lines += ["*INITIAL_VELOCITY_GENERATION", "$        ID      STYP     OMEGA        VX        VY        VZ",
                  _row(pid, 2, 0.0, *sc.parts[pid - 1].initial_velocity), _row(*[0.0] * 6)]
    fixed = node_ids[np.flatnonzero(model.fixed_dofs.all(axis=1))]
    lines += ["*SET_NODE_LIST", _row(1)]
    lines += [_row(*fixed[i:i + 8].tolist()) for i in range(0, fixed.size, 8)]
    lines += ["*BOUNDARY_SPC_SET", _row(1, 0, 1, 1, 1, 1, 1, 1)]
    for contact in sc.contacts:
        slave, master = (next(i + 1 for i, p in enumerate(sc.parts) if p.name == n) for n in contact.parts)
        lines += ["*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE", _row(slave, master, 3, 3),
                  _row(contact.static_friction, contact.dynamic_friction), _row(contact.penalty_scale / 0.1, 1.0)]
    lines += ["*DATABASE_HISTORY_NODE_ID"]
    lines += [f"{node_ids[n]:>10}{name}" for n, name in zip(model.tracked_nodes.tolist(), model.tracked_names,
                                                             strict=True)]
    return [*lines, "*END"]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=Path, default=HERE / "pipe_whip.k")
    args = parser.parse_args(argv)
    sc = scene.load_scene(SCENE)
    model = scene.build_model(sc)
    args.out.write_text("\n".join(deck_text(sc, model)) + "\n")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
