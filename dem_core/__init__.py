"""dem_core: the numba discrete element damage model (after Alzo'ubi, 2009).

Rigid (or deformable) convex blocks, a Voronoi tessellation of the intact rock bonded by
breakable *flaws*, joints as contacts, an explicit time step, and a scene-and-stages workflow.

The public API::

    from dem_core import Scene, build_model, run_stages, Model, Material

    scene = Scene.load("comparisons/scenes/adhikary.json")
    model = build_model(scene)
    records = run_stages(model, scene.stages)

Subpackages (each ``__init__`` says what it holds and what it may import)::

    units        g, MPa, degrees: one definition for both methods
    geometry/    regions, joint sets, Voronoi flaws, the block system (the hand-over type)
    contact/     contacts, their law, forces, detection, corner rounding, materials
    step/        state bundles, kinematics, the explicit step, integration, the critical step
                 (``step/threads/``: the same step on several threads, bit for bit)
    components/  force contributions a scene adds when it has them: gravity, loads, servo,
                 water, cables and liners (``components.support``: their records)
    deformable/  deformable blocks: zones, zone meshes, zone plasticity, their component
    workflow/    scenes, stages, solve settings, the failure search, g-ramps, strength searches,
                 in-situ stress, water tables, loading paths
    output/      monitors and verdicts, rupture surface, model files, VTK, plots
    model.py     ``Model``, the driver: its verbs and its run loop

Importing ``dem_core`` is light: the public names load on first use (PEP 562), so
``import dem_core.geometry`` does not import numba's kernels. Old module paths
(``dem_core.contact.law``, ``dem_core.workflow.scene``, ...) still import, with a DeprecationWarning
(``dem_core._moved``).
"""
from __future__ import annotations

import importlib

from ._moved import install as _install_old_paths

_install_old_paths()

_PUBLIC = {
    "Scene": "dem_core.workflow.scene",
    "build_model": "dem_core.workflow.scene",
    "run_stages": "dem_core.workflow.stages",
    "Model": "dem_core.model",
    "Material": "dem_core.contact.materials",
    "SolveSettings": "dem_core.workflow.settings",
}
__all__ = sorted(_PUBLIC)


def __getattr__(name):
    if name in _PUBLIC:
        value = getattr(importlib.import_module(_PUBLIC[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'dem_core' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + __all__)
