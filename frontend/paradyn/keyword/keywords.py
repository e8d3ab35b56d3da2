"""Every keyword the reader reads (docs/keyword.md): the readers of :mod:`paradyn.keyword.cards`
(mesh, parts, sections, materials, sets, controls) with those of :mod:`paradyn.keyword.parts`
(``*ELEMENT_SHELL_THICKNESS``), :mod:`paradyn.keyword.beams` (``*ELEMENT_BEAM``, ``*SECTION_BEAM``),
:mod:`paradyn.keyword.contacts`, :mod:`paradyn.keyword.loads` and
:mod:`paradyn.keyword.masses`;
:func:`collect` reads a keyword file's blocks with all of them.
"""

from __future__ import annotations

from collections.abc import Callable

from . import beams, cards, contacts, loads, masses, parts
from .cards import KeywordData, _Reading
from .reader import KeywordFile

READERS: dict[str, Callable[[_Reading], None]] = {**cards.READERS, **parts.READERS, **contacts.READERS,
                                                  **loads.READERS, **masses.READERS, **beams.READERS}


def collect(deck: KeywordFile) -> KeywordData:
    """Read every block of ``deck`` (see :func:`paradyn.keyword.cards.collect`) with every reader."""
    return cards.collect(deck, READERS)
