"""Restarting a run from its checkpoint: the deck it belongs to, and a scene edited since.

``paradyn-run SCENE -o OUT --restart`` continues the run in ``OUT`` with the deck already there,
the one its checkpoint belongs to (the engine checks the deck's fingerprint, docs/errors.md). A
scene edited since the run started is compared with that deck: changes to the /control
attributes of ``RESTART_MAY_CHANGE`` (output, history, progress and checkpoint intervals, the time
step floor) are taken into the deck; any other change is refused, naming what differs, since the
checkpoint's state belongs to the old model.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from paradyn import deck
from paradyn._schema import CONTROL, DATASETS, RESTART_MAY_CHANGE


def restart_deck(out_dir: Path, model: deck.Model | None = None) -> Path:
    """The deck of the interrupted run in ``out_dir``; with ``model`` (the scene as it is now), the
    changes a restart may take are written into it and any other change raises ValueError."""
    deck_path, checkpoint = out_dir / "deck.h5", out_dir / "results.checkpoint.h5"
    if not (deck_path.is_file() and checkpoint.is_file()):
        raise ValueError(f"{out_dir} holds no deck.h5 and results.checkpoint.h5 to restart from; give the "
                         f"output folder (-o) of a run that wrote a checkpoint ([run] checkpoint_interval, "
                         f"or a run stopped with Ctrl-C or SIGTERM)")
    if model is None:
        return deck_path
    edited = deck.write_deck(model, out_dir / ".deck.restart.h5")
    try:
        changed = deck_differences(deck.read_deck(deck_path), deck.read_deck(edited))
        refused = [name for name in changed if name.removeprefix("/control ") not in RESTART_MAY_CHANGE]
        if refused:
            raise ValueError(f"the scene changed since the run started ({', '.join(refused)}); a restart continues "
                             f"the run's own model, so run the edited scene anew (without --restart), or undo "
                             f"the change; a restart may change only {', '.join(RESTART_MAY_CHANGE)}")
        if changed:
            os.replace(edited, deck_path)
            print(f"paradyn-run: restart takes the scene's new {', '.join(changed)}")
    finally:
        edited.unlink(missing_ok=True)
    return deck_path


def deck_differences(old: deck.Model, new: deck.Model) -> list[str]:
    """The datasets and /control attributes (``/control name``) whose values differ."""
    changed = [spec.path for spec in DATASETS if not _same(getattr(old, spec.python), getattr(new, spec.python))]
    changed += [f"/control {a.name}" for a in CONTROL if old.control.value(a.name) != new.control.value(a.name)]
    return changed


def _same(a: object, b: object) -> bool:
    if a is None or b is None:
        return a is b
    return bool(np.array_equal(np.asarray(a), np.asarray(b)))
