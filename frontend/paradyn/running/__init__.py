"""Runs: a scene, a keyword deck, a deck file or a deck model through the engine, to results.

:mod:`paradyn.running.workflow` is ``paradyn.run``: it loads the source (:mod:`paradyn.scene`,
:mod:`paradyn.keyword`), builds and sends or writes the deck (:mod:`paradyn.deck`), runs the engine,
reads the results and post-processes them (:mod:`paradyn.results`). The rest is split by job:
starting the engine (:mod:`~paradyn.running.launch`: engines, layouts, machine facts;
:mod:`~paradyn.running.runners`: direct, mpirun, srun, sbatch) and following it
(:mod:`~paradyn.running.engine_process`: progress, warnings, Ctrl-C, exit status); what ``paradyn-run``
shows (:mod:`~paradyn.running.progress`); ``--check`` (:mod:`~paradyn.running.preflight`);
``--restart`` (:mod:`~paradyn.running.restart`); output folders (:mod:`~paradyn.running.folders`); the
engine ``paradyn-run`` starts before its heavy imports (:mod:`~paradyn.running.early_engine`).

The package is named ``running`` so that ``paradyn.run`` stays the function. Nothing here is
imported by the scene, the keyword reader, the deck or the results; the studies and the commands
build on it.
"""
