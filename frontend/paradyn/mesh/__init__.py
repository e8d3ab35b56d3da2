"""Meshes: 4-node quadrilateral shell meshes, by formula (:mod:`paradyn.mesh.geometry`: cylinders
and plates, numpy) or read from files (:mod:`paradyn.mesh.files`: gmsh files with their tags and
physical groups, meshio for the rest).

A mesh knows nothing of scenes, decks or runs: the scene (:mod:`paradyn.scene`) and the keyword
reader (:mod:`paradyn.keyword`) turn meshes into deck models.
"""
