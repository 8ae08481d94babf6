"""Old import paths of the modules that moved into subpackages, kept for one release.

``dem_core`` installs ``OldPaths`` on ``sys.meta_path``: importing an old name (``dem_core.law``)
gives the new module itself (``dem_core.contact.law``; private names, ``mock.patch`` targets
and ``isinstance`` keep working) and a ``DeprecationWarning`` naming the new path. The tree
itself holds no copies of the old files.
"""
from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
import warnings

MOVED = {
    "dem_core.blocks": "dem_core.geometry.blocks",
    "dem_core.simple_blocks": "dem_core.geometry.simple_blocks",
    "dem_core.contacts": "dem_core.contact.contacts",
    "dem_core.law": "dem_core.contact.law",
    "dem_core.forces": "dem_core.contact.forces",
    "dem_core.detection": "dem_core.contact.detection",
    "dem_core.rounding": "dem_core.contact.rounding",
    "dem_core.materials": "dem_core.contact.materials",
    "dem_core.elastic": "dem_core.contact.elastic",
    "dem_core.components.boundary_points": "dem_core.contact.boundary_points",
    "dem_core.state": "dem_core.step.state",
    "dem_core.kinematics": "dem_core.step.kinematics",
    "dem_core.integration": "dem_core.step.integration",
    "dem_core.relaxation": "dem_core.step.relaxation",
    "dem_core.critical_step": "dem_core.step.critical_step",
    "dem_core.components.nodes": "dem_core.step.nodes",
    "dem_core.parallel": "dem_core.step.threads.parallel",
    "dem_core.region": "dem_core.step.threads.region",
    "dem_core.atomics": "dem_core.step.threads.atomics",
    "dem_core.support": "dem_core.components.support",
    "dem_core.zones": "dem_core.deformable.zones",
    "dem_core.zone_mesh": "dem_core.deformable.zone_mesh",
    "dem_core.zone_plasticity": "dem_core.deformable.zone_plasticity",
    "dem_core.components.deformable": "dem_core.deformable.component",
    "dem_core.components.deformable_bc": "dem_core.deformable.held",
    "dem_core.scene": "dem_core.workflow.scene",
    "dem_core.stages": "dem_core.workflow.stages",
    "dem_core.limit": "dem_core.workflow.limit",
    "dem_core.gravity_ramp": "dem_core.workflow.gravity_ramp",
    "dem_core.strength": "dem_core.workflow.strength",
    "dem_core.loading": "dem_core.workflow.loading",
    "dem_core.insitu": "dem_core.workflow.insitu",
    "dem_core.water": "dem_core.workflow.water",
    "dem_core.monitor": "dem_core.output.monitor",
    "dem_core.rupture": "dem_core.output.rupture",
    "dem_core.io": "dem_core.output.io",
    "dem_core.vtk": "dem_core.output.vtk",
    "dem_core.plot": "dem_core.output.plot",
}


class OldPaths(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds the old module names of ``MOVED`` and loads them as their new modules."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname in MOVED:
            return importlib.util.spec_from_loader(fullname, self)
        return None

    def create_module(self, spec):
        warnings.warn(f"{spec.name} moved to {MOVED[spec.name]}; the old path goes in the "
                      "next release", DeprecationWarning, stacklevel=2)
        return importlib.import_module(MOVED[spec.name])

    def exec_module(self, module):
        """Nothing to run: the new module is already imported."""


def renamed(mapping: dict, renames: dict, where: str, noun: str = "key",
            error=ValueError) -> dict:
    """``mapping`` with each old name of ``renames`` (old -> new) replaced by its new one, a
    DeprecationWarning naming both for each; ``error`` (naming ``where``) when a mapping gives
    both spellings. The one rule for names renamed in this release (case parameters, the
    zone-strength keys)."""
    if not any(k in mapping for k in renames):
        return mapping
    out = {}
    for k, v in mapping.items():
        new = renames.get(k)
        if new is None:
            out[k] = v
            continue
        if new in mapping:
            raise error(f"{where}: give {new!r} only, not also its old name {k!r}")
        warnings.warn(f"{where}: the {noun} {k!r} is now {new!r} (the old name goes in the "
                      "next release)", DeprecationWarning, stacklevel=3)
        out[new] = v
    return out


def install() -> None:
    """Put ``OldPaths`` first on ``sys.meta_path`` (once)."""
    if not any(isinstance(f, OldPaths) for f in sys.meta_path):
        sys.meta_path.insert(0, OldPaths())
