"""ParaDyn's warnings in Python: the categories, and how :func:`paradyn.run` issues them.

A run says what looks wrong in three places: the reader of an LS-DYNA keyword deck (cards and
fields left out or read differently, the units), the check before it (:mod:`paradyn.running.preflight`:
values that look like another unit system's, a model where nothing moves, settings far outside
the usual) and the engine (``paradyn-engine: warning:`` lines: a requested step above the stable
one, initial contact penetrations). ``paradyn-run`` prints them; :func:`paradyn.run` issues each
through Python's :mod:`warnings` (unless a :class:`~paradyn.running.progress.RunProgress` display
shows them), keeps them in ``EngineRun.warnings`` and writes them to ``summary.json``
(docs/python.md, "Warnings").

The categories are :class:`ParaDynWarning` and its kinds, :class:`ModelWarning` (the check's),
:class:`KeywordWarning` (the keyword deck reader's: cards left out, the units) and
:class:`EngineWarning` (the engine's), so that the usual filters apply::

    import warnings, paradyn
    warnings.simplefilter("error", paradyn.ModelWarning)     # a likely unit mistake stops the script
    warnings.simplefilter("ignore", paradyn.EngineWarning)   # the engine's are not shown

Each warning points at the caller's line (the first frame outside the ``paradyn`` package) and is
shown every time it is issued (a second run of the same scene says it again), not once per line as
Python's default would.
"""

from __future__ import annotations

import sys
import warnings
from collections.abc import Iterable
from pathlib import Path

ENGINE_PREFIX = "paradyn-engine: "   # the engine's lines: "paradyn-engine: warning: ..."
CHECK_PREFIX = "paradyn: "           # the check's, as EngineRun.warnings keeps them: "paradyn: warning: ..."
_PACKAGE = str(Path(__file__).resolve().parents[1])   # frontend/paradyn (or site-packages/paradyn)


class ParaDynWarning(UserWarning):
    """Something in a run that runs, but likely not as meant (the base of ParaDyn's warnings)."""


class ModelWarning(ParaDynWarning):
    """The check before a run: a value that looks like another unit system's (a 2 m shell, a
    density in tonne/mm^3), a model where nothing moves, a setting far outside the usual."""


class KeywordWarning(ParaDynWarning):
    """An LS-DYNA keyword deck's cards or fields that ParaDyn leaves out or reads in its own way,
    and the units it read the deck in (docs/keyword.md)."""


class EngineWarning(ParaDynWarning):
    """The engine's own warnings at set-up and during the run (initial contact penetrations, a
    requested step above the stable one)."""


def check_line(message: str) -> str:
    """A warning of the check as ``EngineRun.warnings`` and ``summary.json`` keep it."""
    return f"{CHECK_PREFIX}warning: {message}"


def message_of(line: str) -> str:
    """The message of a kept line (``paradyn-engine: warning: X`` and ``paradyn: warning: X`` give X)."""
    for prefix in (ENGINE_PREFIX, CHECK_PREFIX):
        if line.startswith(prefix):
            line = line[len(prefix):]
            break
    return line.removeprefix("warning: ")


def issue(messages: Iterable[str], category: type[ParaDynWarning]) -> None:
    """Issue each message as a ``category`` warning at the caller's line outside this package,
    every time (no once-per-line registry)."""
    for message in messages:
        filename, lineno, module, module_globals = _caller()
        warnings.warn_explicit(message, category, filename, lineno, module=module, registry=None,
                               module_globals=module_globals)


def _caller() -> tuple[str, int, str, dict | None]:
    """The file, line, module name and globals of the first frame outside the paradyn package."""
    frame = sys._getframe(1)
    while frame.f_back is not None and frame.f_code.co_filename.startswith(_PACKAGE):
        frame = frame.f_back
    name = frame.f_globals.get("__name__", "<unknown>")
    return frame.f_code.co_filename, frame.f_lineno, str(name), frame.f_globals


__all__ = ["EngineWarning", "KeywordWarning", "ModelWarning", "ParaDynWarning", "check_line", "issue", "message_of"]
