"""Whether a continuum model's fixed displacements hold it against rigid-body motion.

A plane body that is not held in x, in y and against rotation has a singular stiffness: every
Newton solve fails and a stage returns ``converged=False`` with no reason. Each fixed component
c at a point (x, y) removes a rigid motion u = (a - w (y - y_c), b + w (x - x_c)) (a, b: the
translations, w: the rotation about the model's centre (x_c, y_c)) from the free ones when its
row, [1, 0, -(y - y_c)] for c = x or [0, 1, x - x_c] for c = y, adds to the rank of the rows
seen so far; the body is held when the rank is 3 (e.g. Zienkiewicz & Taylor, The Finite
Element Method, vol. 1, "Singular stiffness: rigid-body modes"). Springs and tractions do not
hold a body here (the continuum has none of the former; the latter do not constrain).
"""
from __future__ import annotations

import numpy as np

__all__ = ["free_rigid_motions", "check_supported"]


def _rows(model) -> np.ndarray:
    """(m, 3) one row per fixed displacement component (module docstring), lengths scaled by
    the model's size."""
    xy = model.V.tabulate_dof_coordinates()[:, :2]
    bs = model.V.dofmap.index_map_bs
    dofs = [np.asarray(d, dtype=np.int64) for _, _, _, d in model._dirichlet]
    if not dofs or not sum(len(d) for d in dofs):
        return np.zeros((0, 3))
    dofs = np.unique(np.concatenate(dofs))
    node, comp = dofs // bs, dofs % bs
    centre = 0.5 * (xy.min(axis=0) + xy.max(axis=0))
    rel = (xy[node] - centre) / max(float(np.ptp(xy, axis=0).max()), 1e-300)
    rows = np.zeros((len(dofs), 3))
    rows[comp == 0, 0], rows[comp == 0, 2] = 1.0, -rel[comp == 0, 1]
    rows[comp == 1, 1], rows[comp == 1, 2] = 1.0, rel[comp == 1, 0]
    return rows


def free_rigid_motions(model) -> list:
    """The rigid-body motions a ``ContinuumModel``'s fixed displacements leave free: a list of
    "x translation", "y translation", "rotation about (x, y) m" (empty: held)."""
    rows = _rows(model)
    held = rows.T @ rows
    w, v = np.linalg.eigh(held)
    free = v[:, w <= 1e-10 * max(float(w.max(initial=0.0)), 1.0)]
    if free.shape[1] == 0:
        return []
    out = []
    if not np.any(rows[:, 0]):
        out.append("x translation")
    if not np.any(rows[:, 1]):
        out.append("y translation")
    if np.any(np.abs(free[2]) > 1e-9):
        xy = model.V.tabulate_dof_coordinates()[:, :2]
        centre = 0.5 * (xy.min(axis=0) + xy.max(axis=0))
        size = float(np.ptp(xy, axis=0).max())
        k = int(np.argmax(np.abs(free[2])))
        a, b, rot = free[:, k]
        pivot = centre + size * np.array([-b / rot, a / rot])      # where u = 0
        where = (f" about ({pivot[0]:.4g}, {pivot[1]:.4g}) m" if rows.size and
                 np.all(np.isfinite(pivot)) and not out else "")
        out.append("rotation" + where)
    return out


def check_supported(model, where="continuum") -> None:
    """ValueError naming the rigid-body motions ``model`` is free to make (module docstring),
    before any solve."""
    free = free_rigid_motions(model)
    if free:
        raise ValueError(f"{where}: the fixed displacements leave the model free to move as a "
                         f"rigid body ({', '.join(free)}): its stiffness is singular and no "
                         "solve can converge; fix displacements on a boundary, e.g. the base "
                         "in x and y (a scene boundary {\"group\": \"base\", \"x\": true, "
                         "\"y\": true})")
