"""Studies: what accuracy costs in time (``paradyn.study`` and ``paradyn-study``, docs/accuracy-cost.md).

The sweep (:mod:`paradyn.studies.sweep`, ``paradyn.study``); its settings and the ``[study]`` table
(:mod:`~paradyn.studies.spec`); knobs and designs (:mod:`~paradyn.studies.design`); runs cached by
deck content (:mod:`~paradyn.studies.runs`); quantities and Richardson errors
(:mod:`~paradyn.studies.error`); the front, knob steps and target (:mod:`~paradyn.studies.analysis`);
CSV, JSON and markdown (:mod:`~paradyn.studies.output`); the Pareto plot
(:mod:`~paradyn.studies.plot`); the command (:mod:`~paradyn.studies.cli`).

A study runs scenes (:mod:`paradyn.running`) and reads their results (:mod:`paradyn.results`); only
the commands import it. The package is named ``studies`` so that ``paradyn.study`` stays the function.
"""
