"""The continuum model of a ``dem_core.workflow.scene.Scene``: the same regions meshed, the same
monitoring points, the same boundaries (one definition for both methods).

A scene boundary fixes velocity components of a block group; here it fixes the displacement
components (x, y) of the boundary facets of that group. The continuum has no blocks, so a group
must be one the mesh can see: a side of the model's box (``{"touching": side}``) or a union or
difference of such groups. (A "minus" removes the other group's side from the predicate only
where it is a different side: fixing the base fully and the sides in x, the usual centrifuge and
slope boundary, is the same in both methods.) Other selectors raise ValueError naming the group.
"""
from __future__ import annotations

import numpy as np

from .mesh import mesh_from_geometry
from .supports import check_supported

__all__ = ["mesh_from_scene", "apply_boundaries", "side_sets", "scene_bounds", "scene_top",
           "apply_insitu", "apply_water"]


def mesh_from_scene(scene, h, geometry=None, **options):
    """Mesh a scene's regions (or ``geometry``, e.g. the section without its joints) with the
    scene's monitoring points; ``options`` go to ``mesh.mesh_from_geometry``."""
    return mesh_from_geometry(geometry or scene.geometry, h, points=scene.points, **options)


def side_sets(scene, group: str) -> set:
    """The box sides ("bottom", "top", "left", "right") a scene group stands for."""
    if group not in scene.groups:
        raise ValueError(f"continuum boundary on group {group!r}: only scene groups made of box "
                         f"sides can be applied to a mesh (scene groups: {sorted(scene.groups)})")
    (kind, arg), = scene.groups[group].items()
    if kind == "touching":
        return {arg}
    if kind == "union":
        return set().union(*(side_sets(scene, g) for g in arg))
    if kind == "minus":
        return side_sets(scene, arg[0]) - side_sets(scene, arg[1])
    raise ValueError(f"continuum boundary on group {group!r}: selector {kind!r} has no facets "
                     "in a mesh; use box sides (touching, union, minus)")


def _predicate(sides, bounds, tol):
    x0, y0, x1, y1 = bounds
    tests = {"left": lambda x: np.abs(x[0] - x0) < tol, "right": lambda x: np.abs(x[0] - x1) < tol,
             "bottom": lambda x: np.abs(x[1] - y0) < tol, "top": lambda x: np.abs(x[1] - y1) < tol}
    chosen = [tests[s] for s in sorted(sides)]
    return lambda x: np.any([t(x) for t in chosen], axis=0)


def apply_boundaries(model, scene, bounds) -> None:
    """Fix the displacement components of every scene boundary on ``model``
    (``continuum_ref.model.ContinuumModel``); ``bounds`` = (x0, y0, x1, y1) of the model, m.
    ValueError when they leave the model free to move as a rigid body (``supports``: no
    boundary, or one that holds only y): every solve would fail with no reason given."""
    tol = 1e-9 * max(bounds[2] - bounds[0], bounds[3] - bounds[1])
    for b in scene.boundaries:
        comps = tuple(c for c, on in ((0, b.x), (1, b.y)) if on)
        if comps:
            model.fix(_predicate(side_sets(scene, b.group), bounds, tol), components=comps)
    check_supported(model, f"scene {scene.name!r}: continuum boundaries "
                           f"{[b.group for b in scene.boundaries]}")


def scene_bounds(scene) -> tuple:
    """(x0, y0, x1, y1) of the scene's regions, m."""
    xy = np.concatenate([np.asarray(r.exterior, float) for r in scene.geometry.regions])
    return float(xy[:, 0].min()), float(xy[:, 1].min()), float(xy[:, 0].max()), \
        float(xy[:, 1].max())


def scene_top(scene) -> np.ndarray:
    """(m, 2) polyline of the top of the scene's regions (their upper envelope, the surface an
    in-situ field with ``surface=None`` measures depth from; the DEM takes the same from its
    blocks' outer edges)."""
    from dem_core.workflow.insitu import top_surface
    edges = []
    for r in scene.geometry.regions:
        p = np.asarray(r.exterior, dtype=np.float64)
        edges.append(np.column_stack([p, np.roll(p, -1, axis=0)]))
    return top_surface(np.concatenate(edges))


def apply_insitu(model, scene, stage) -> None:
    """Give ``model`` (ContinuumModel) the in-situ stress of a scene's ``insitu`` stage."""
    model.set_stress_field(stage, top=scene_top(scene))


def apply_water(model, water_table, solve=False):
    """Give ``model`` the pore pressure of a ``dem_core.workflow.water.WaterTable`` (effective-stress
    analysis). ``solve=False``: set it (``ContinuumModel.set_pore_pressure``), before solving
    gravity; returns None. ``solve=True``: bring it in on a model at equilibrium with load
    stepping (``ContinuumModel.solve_pore_pressure``, the water stage of a staged
    sequence); returns the StageResult."""
    water_table.check()
    if solve:
        return model.solve_pore_pressure(water_table.pressure)
    model.set_pore_pressure(water_table.pressure)
    return None
