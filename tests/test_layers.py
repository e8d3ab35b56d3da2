"""The package's import structure (docs/architecture.md, "The frontend"): the subpackages stand in
layers, each importing only the layers below it, and no module imports itself back through others."""

from __future__ import annotations

import ast
from pathlib import Path

import paradyn

PACKAGE = Path(paradyn.__file__).resolve().parent

# The units of the package (a subpackage, or top-level modules taken together) ...
UNITS = {
    "base": ("paradyn._schema", "paradyn.atomic_write", "paradyn.arguments"),
    "deck": ("paradyn.deck",),
    "mesh": ("paradyn.mesh",),
    "scene": ("paradyn.scene",),
    "results": ("paradyn.results",),
    "keyword": ("paradyn.keyword",),
    "running": ("paradyn.running",),
    "studies": ("paradyn.studies",),
    "commands": ("paradyn", "paradyn.cli", "paradyn.cli_parser", "paradyn.commands", "paradyn.benchmark"),
}
# ... and their layers, the lowest first. A module imports its own unit and the units of lower
# layers only; the units of one layer do not import each other. The deck and meshes are data;
# a scene builds a deck model from meshes, and results are read with the deck beside them; a
# keyword deck becomes a scene; a run takes any of them to results; a study runs scenes; the
# commands and the package's lazy names (paradyn.run, paradyn.read, ...) sit on top.
LAYERS = [("base",), ("deck", "mesh"), ("scene", "results"), ("keyword",), ("running",), ("studies",), ("commands",)]
# imports of a higher layer for annotations only (under ``if TYPE_CHECKING:``, never run), and why
ANNOTATIONS_ONLY = {
    ("paradyn.results.reading", "paradyn.running.engine_process"):
        "Results.engine_run holds the EngineRun that paradyn.run fills in",
}


def _modules() -> dict[str, Path]:
    """Every module of the package by its dotted name (a package by its own name, for its __init__)."""
    found = {}
    for path in PACKAGE.rglob("*.py"):
        parts = ("paradyn", *path.relative_to(PACKAGE).with_suffix("").parts)
        found[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return found


MODULES = _modules()


def _type_checking_nodes(tree: ast.AST) -> set[ast.AST]:
    """The statements under ``if TYPE_CHECKING:``."""
    inside: set[ast.AST] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for statement in node.body:
                inside.update(ast.walk(statement))
    return inside


def _imports(name: str) -> dict[str, bool]:
    """The paradyn modules ``name`` imports anywhere in its text (lazy imports and imports for
    annotations included), each as the module it names (``from paradyn.deck import items``:
    ``paradyn.deck.items``; ``from paradyn.deck import Model``: ``paradyn.deck``), with whether
    every import of it is for annotations only."""
    path = MODULES[name]
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    tree = ast.parse(path.read_text())
    annotations = _type_checking_nodes(tree)
    found: dict[str, bool] = {}

    def add(module: str, node: ast.AST) -> None:
        if module != name:
            found[module] = found.get(module, True) and node in annotations

    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name in MODULES:
                    add(alias.name, node)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join([*base, node.module] if node.module else base)
            else:
                target = node.module or ""
            for alias in node.names:
                if f"{target}.{alias.name}" in MODULES:
                    add(f"{target}.{alias.name}", node)
                elif target in MODULES:
                    add(target, node)
    return found


GRAPH = {name: _imports(name) for name in MODULES}


def _unit(module: str) -> str | None:
    for unit, roots in UNITS.items():
        for root in roots:
            if module == root or (root != "paradyn" and module.startswith(root + ".")):
                return unit
    return None


def _layer(unit: str) -> int:
    return next(i for i, layer in enumerate(LAYERS) if unit in layer)


def test_every_module_has_its_unit_and_every_unit_its_layer() -> None:
    assert sorted(m for m in MODULES if _unit(m) is None) == []
    assert sorted(u for layer in LAYERS for u in layer) == sorted(UNITS)


def test_no_layer_imports_a_higher_one_or_its_neighbour() -> None:
    """results does not import the runs, the deck not the scene, the scene not the keyword reader,
    ... (the layers above); a higher layer's type in an annotation is named in ANNOTATIONS_ONLY."""
    wrong = []
    for module, imported in GRAPH.items():
        for target, annotation_only in imported.items():
            here, there = _unit(module), _unit(target)
            if here == there or _layer(there) < _layer(here):
                continue
            if annotation_only and (module, target) in ANNOTATIONS_ONLY:
                continue
            wrong.append(f"{module} ({here}) imports {target} ({there})")
    assert wrong == []
    for module, target in ANNOTATIONS_ONLY:   # still there, still for annotations only
        assert GRAPH[module].get(target) is True, (module, target)


def test_the_layer_check_sees_an_upward_import() -> None:
    """The check itself: a deck module importing the scene, or results importing a run at run
    time, would be found."""
    assert _layer(_unit("paradyn.scene.building")) > _layer(_unit("paradyn.deck.files"))
    assert _layer(_unit("paradyn.running.launch")) > _layer(_unit("paradyn.results.reading"))
    assert GRAPH["paradyn.running.workflow"]["paradyn.scene"] is False   # a run-time import is seen as one
    assert GRAPH["paradyn.results.reading"]["paradyn.running.engine_process"] is True


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
