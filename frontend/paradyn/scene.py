"""Scenes: the user's TOML description of a ParaDyn run (see docs/scene.md), turned into a deck model.

``load_scene(path)`` parses and checks the file (unknown keys, missing keys, types, ranges) and
returns a :class:`Scene`; ``build_model(scene)`` meshes the parts and returns a :class:`deck.Model`.
Every problem raises :class:`SceneError` with a message that starts with the scene file path.

This module is the scene's public face; the work is split by job: the data types are in
:mod:`paradyn.scene_specs`, reading and checking a file in :mod:`paradyn.scene_reading`, building
the deck model in :mod:`paradyn.scene_building`.
"""

from __future__ import annotations

from paradyn.scene_building import build_model
from paradyn.scene_reading import load_scene
from paradyn.scene_specs import (
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
    RigidWallSpec,
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
    "RigidWallSpec",
    "RunSettings",
    "Scene",
    "SceneError",
    "TrackSpec",
    "build_model",
    "load_scene",
]
