"""LS-DYNA keyword decks (``.k``, docs/keyword.md) read into a ParaDyn scene and deck model.

The work is split by job: the file format (columns, long and free format, ``*INCLUDE``,
``*PARAMETER``) in :mod:`paradyn.keyword.reader`; the subset's card layouts and records in
:mod:`paradyn.keyword.cards` (0.0 meaning the default: :mod:`paradyn.keyword.defaults`), parts by
thickness in :mod:`paradyn.keyword.parts`, contacts in :mod:`paradyn.keyword.contacts`, loads and
motions in :mod:`paradyn.keyword.loads` with :mod:`paradyn.keyword.curves`, materials' curves in
:mod:`paradyn.keyword.materials`, added masses in :mod:`paradyn.keyword.masses`, rigid bodies and
welds in :mod:`paradyn.keyword.rigid`, rigid walls in :mod:`paradyn.keyword.walls`, all of them gathered by
:mod:`paradyn.keyword.keywords`; unit systems in :mod:`paradyn.keyword.units`; the mesh with its ids,
fixed dofs and velocities in :mod:`paradyn.keyword.mesh`; the scene and deck model in
:mod:`paradyn.keyword.scene` (``paradyn.read_keyword``). A keyword deck becomes the scene's specs
(:mod:`paradyn.scene`) and a :mod:`paradyn.deck` model; nothing here imports the runs or the results.
"""
