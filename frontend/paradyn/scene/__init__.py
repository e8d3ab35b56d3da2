"""Scenes: the user's TOML description of a ParaDyn run (see docs/scene.md), turned into a deck model.

``load_scene(path)`` parses and checks the file (unknown keys, missing keys, types, ranges) and
returns a :class:`Scene`; ``build_model(scene)`` meshes the parts and returns a :class:`deck.Model`.
Every problem raises :class:`SceneError` with a message that starts with the scene file path.

This package's names are the scene's public face; the work is split by job: the data types are in
:mod:`paradyn.scene.specs`, typed access to a scene's tables in :mod:`paradyn.scene.tables`,
reading and checking a file in :mod:`paradyn.scene.reading`, building the deck model in
:mod:`paradyn.scene.building`; a scene built in Python (``paradyn.Scene``) in
:mod:`paradyn.scene.builder`, and its TOML text in :mod:`paradyn.scene.toml_writing`. Meshes come
from :mod:`paradyn.mesh`; the scene builds a :mod:`paradyn.deck` model and imports nothing of the
runs, the results or the keyword reader.
"""

from __future__ import annotations

from .building import build_model
from .reading import load_scene
from .specs import (
    DOF_GROUPS,
    HOURGLASS_FORMS,
    MATERIAL_MODELS,
    ContactSpec,
    CurveSpec,
    CylinderGeometry,
    FileGeometry,
    FixSpec,
    Geometry,
    LoadSpec,
    MaterialSpec,
    PartSpec,
    PlateGeometry,
    PrescribeSpec,
    PressureSpec,
    RunSettings,
    Scene,
    SceneError,
    TrackSpec,
)

__all__ = [
    "DOF_GROUPS",
    "HOURGLASS_FORMS",
    "MATERIAL_MODELS",
    "ContactSpec",
    "CurveSpec",
    "CylinderGeometry",
    "FileGeometry",
    "FixSpec",
    "Geometry",
    "LoadSpec",
    "MaterialSpec",
    "PartSpec",
    "PlateGeometry",
    "PrescribeSpec",
    "PressureSpec",
    "RunSettings",
    "Scene",
    "SceneError",
    "TrackSpec",
    "build_model",
    "load_scene",
]
