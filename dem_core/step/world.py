"""The two records the step takes: the world (blocks, contacts and what their kernels read)
and its parts (the force components).

Both are ``typing.NamedTuple``s of bundles, which numba takes whole, so a kernel's signature
is ``(nsteps, time, integ, world, parts)`` however many components the scene has. Adding a
component touches its own file, ``Parts``, ``run.add_other_forces`` (one line) and the driver
that builds its bundle; nothing else.

World
    state     ``state.BlockState``: poses, velocities, forces (changes every step)
    props     ``state.BlockProps``: masses, fixity, shapes (changes between stages)
    contacts  ``contact.contacts.Contacts``: the contact arrays (replaced by a search)
    strength  (nm, 7) float64: the material table's strength rows
              (``contact.materials.MaterialTable.strength_array``)
    cracks    ``state.CrackLog``: the bond failures so far
    corners   ``contact.rounding.Rounding``: corner centres (empty: sharp corners)
    zones     ``deformable.component.Deformable``: the deformable blocks' zones (empty:
              every block rigid); the contact kernels read their points

Parts (each empty where the scene has none: its kernel then loops over nothing)
    gravity, loads, water, cables, liners, servo: ``dem_core.components``' bundles
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["World", "Parts"]


class World(NamedTuple):
    state: object
    props: object
    contacts: object
    strength: np.ndarray
    cracks: object
    corners: object
    zones: object


class Parts(NamedTuple):
    gravity: object
    loads: object
    water: object
    cables: object
    liners: object
    servo: object
