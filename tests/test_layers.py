"""The package's import structure (docs/architecture.md, "The frontend"): no module imports itself
back through others, and the reading, plotting and writing of results stay apart."""

from __future__ import annotations

import ast
from pathlib import Path

import paradyn

PACKAGE = Path(paradyn.__file__).resolve().parent


def _modules() -> dict[str, Path]:
    """Every module of the package by its dotted name (a package by its own name, for its __init__)."""
    found = {}
    for path in PACKAGE.rglob("*.py"):
        parts = ("paradyn", *path.relative_to(PACKAGE).with_suffix("").parts)
        found[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return found


MODULES = _modules()


def _imports(name: str) -> set[str]:
    """The paradyn modules ``name`` imports anywhere in its text (lazy imports and imports for
    annotations included), each as the module it names: ``from paradyn.deck import stream`` names
    ``paradyn.deck.stream``, ``from paradyn.deck import Model`` names ``paradyn.deck``."""
    path = MODULES[name]
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names if alias.name in MODULES)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join([*base, node.module] if node.module else base)
            else:
                target = node.module or ""
            for alias in node.names:
                if f"{target}.{alias.name}" in MODULES:
                    found.add(f"{target}.{alias.name}")
                elif target in MODULES:
                    found.add(target)
    return found - {name}


GRAPH = {name: _imports(name) for name in MODULES}


def test_no_module_of_the_package_imports_itself_back() -> None:
    """A circle-free package: in particular plots reads results through paradyn.results.reading
    only, and reading draws through paradyn.results.figures without importing plots."""
    plots, reading, figures = (GRAPH[f"paradyn.results.{m}"] for m in ("plots", "reading", "figures"))
    assert "paradyn.results" not in plots and "paradyn.results.reading" in plots
    assert "paradyn.results.plots" not in reading and "paradyn.results.reading" not in figures

    def reaches(start: str, target: str, seen: set[str]) -> bool:
        for nxt in GRAPH.get(start, ()):
            if nxt == target or (nxt not in seen and reaches(nxt, target, seen | {nxt})):
                return True
        return False

    circles = sorted(name for name in GRAPH if reaches(name, name, {name}))
    assert circles == []
