"""The examples of the docstrings run (issue 18): each module's ``Examples`` sections, through
doctest, in a temporary folder (the examples write ``runs/...``). Examples that need files of a
finished run are marked ``# doctest: +SKIP`` where they stand."""

from __future__ import annotations

import doctest
import importlib

import pytest

MODULES = ("paradyn.scene.builder", "paradyn.results.reading", "paradyn.results.figures", "paradyn.scene.toml_writing")


@pytest.mark.parametrize("name", MODULES)
def test_examples_run(name: str, tmp_path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("PYVISTA_OFF_SCREEN", "true")
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE, verbose=False)
    assert result.failed == 0, f"{result.failed} of the examples of {name} failed (see the output above)"
    assert result.attempted > 0, f"{name} has no examples"
