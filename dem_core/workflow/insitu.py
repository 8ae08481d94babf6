"""In-situ stress: an initial stress field both methods start from, and the stage that sets it.

The field (compression positive, Pa), as UDEC's in-situ stress with gradients::

    depth(x, y) = max(0, surface(x) - y)                      m, vertically below the surface
    sxx = sxx0 + gxx depth,  syy = syy0 + gyy depth,  sxy = sxy0 + gxy depth
    with k given:  sxx = k syy  (the horizontal stress is k times the vertical one)

``surface``: a level (m), a polyline [[x, y], ...] (increasing x; held flat beyond its ends) or
None, the top of the model (the upper envelope of the geometry's regions, so that a slope's
stress grows with depth below its own face). The out-of-plane stress (continuum, plane strain)
is taken equal to sxx. A geostatic field is ``gyy = rho g`` (times the g-level) with ``k``
(``InSitu.geostatic``).

DEM: each contact gets the traction of the field on its plane, ``sn = n . S . n`` and
``ts = t . S . n`` (n from A into B, t = (-n_y, n_x): the law's convention, ``law.py``), at the
contact point; the law carries on from it by increments. Continuum
(``continuum_ref.model.ContinuumModel.set_stress_field``): the same field at every quadrature
point. A field in equilibrium with gravity (``gyy = rho g``, ``sxy`` and the x-gradients zero,
under a flat surface) leaves a rigid-block model in equilibrium at step 0 up to the lumping of
each edge's traction at its two ends.

The thesis's own initialisation (solve gravity with strong properties, then give the flaws their
real strengths, thesis 5.2) is ``strong_then_real``: stages, because a strength change moves no
stress (``law.py``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .plausibility import check_stress
from .water import check_surface, surface_height

__all__ = ["InSitu", "top_surface", "model_top"]


def top_surface(edges) -> np.ndarray:
    """(m, 2) polyline of the upper envelope of segments ``edges`` ((e, 4): x1, y1, x2, y2):
    for each x the highest point of a segment over it, sampled at every end point's x (the
    envelope of a polygon's boundary is linear between them)."""
    e = np.asarray(edges, dtype=np.float64)
    xs = np.unique(e[:, [0, 2]])
    ys = np.concatenate([_envelope(e, xs[i:i + 512]) for i in range(0, len(xs), 512)])
    return np.column_stack([xs, ys])


def model_top(model) -> np.ndarray:
    """The top of a DEM model as built: the upper envelope of the free (outer) edges of its
    active blocks (``BlockSystem.meta["free_edges"]``; without it, of every block edge)."""
    bs, active = model.blocks, model.props.active
    fe = bs.meta.get("free_edges")
    if fe is not None:
        keep = active[np.asarray(fe["block"])] != 0
        e = np.column_stack([fe["p0"], fe["p1"]])[keep]
    else:
        v, off = bs.vertices, bs.vertex_offsets
        nxt = np.arange(len(v)) + 1
        nxt[off[1:] - 1] = off[:-1]
        owner = np.repeat(np.arange(bs.n_blocks), np.diff(off))
        e = np.column_stack([v, v[nxt]])[active[owner] != 0]
    return top_surface(e)


def _envelope(e, x):
    x1, y1, x2, y2 = e[:, 0:1], e[:, 1:2], e[:, 2:3], e[:, 3:4]
    lo, hi = np.minimum(x1, x2), np.maximum(x1, x2)
    inside = (x[None, :] >= lo - 1e-12) & (x[None, :] <= hi + 1e-12)
    dx = np.where(hi > lo, x2 - x1, 1.0)
    t = np.where(hi > lo, (x[None, :] - x1) / dx, 0.0)
    y = np.where(hi > lo, y1 + t * (y2 - y1), np.maximum(y1, y2))
    return np.where(inside, y, -np.inf).max(axis=0)


@dataclass(frozen=True)
class InSitu:
    """An in-situ stress field (module docstring) and, as a stage (kind "insitu"), its
    assignment to every contact of the model. Stresses Pa (compression +), gradients Pa/m of
    depth, ``k`` >= 0 or None, ``surface`` a level (m), a polyline or None (top of the model)."""

    sxx: float = 0.0
    syy: float = 0.0
    sxy: float = 0.0
    gxx: float = 0.0
    gyy: float = 0.0
    gxy: float = 0.0
    k: float | None = None
    surface: float | tuple | None = None

    @classmethod
    def geostatic(cls, density, k, g_level=1.0, surface=None) -> "InSitu":
        """The field of rock of ``density`` (kg/m^3) at ``g_level`` under its own weight:
        sv = density g depth (g = ``units.STANDARD_GRAVITY``, as the DEM's and the
        continuum's gravity), sh = k sv."""
        from ..units import STANDARD_GRAVITY
        return cls(gyy=float(density) * STANDARD_GRAVITY * float(g_level), k=k, surface=surface)

    def check(self, i=0, groups=(), materials=()):
        where = f"stage {i} (insitu)"
        vals = dict(sxx=self.sxx, syy=self.syy, sxy=self.sxy, gxx=self.gxx, gyy=self.gyy,
                    gxy=self.gxy)
        bad = [n for n, v in vals.items() if not math.isfinite(float(v))]
        if bad:
            raise ValueError(f"{where}: {bad} must be finite (Pa, Pa/m), got "
                             f"{[vals[n] for n in bad]}")
        check_stress(vals, where)
        if self.k is not None:
            if not (math.isfinite(self.k) and self.k >= 0):
                raise ValueError(f"{where}: k = sh / sv = {self.k!r} must be finite and >= 0")
            if self.sxx or self.gxx:
                raise ValueError(f"{where}: give either k or sxx, gxx (k sets sxx = k syy)")
        if self.surface is not None:
            check_surface(self.surface, where)

    def depth(self, x, y, top=None) -> np.ndarray:
        """Depth (m) below the surface of points (x, y); ``top``: the model's top polyline,
        used when ``surface`` is None."""
        x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
        s = self.surface
        if s is None:
            if top is None:
                raise ValueError("insitu: surface None (the top of the model) needs the model's "
                                 "top polyline")
            s = top
        return np.maximum(surface_height(s, x) - y, 0.0)

    def stress(self, x, y, top=None) -> tuple:
        """(sxx, syy, sxy) arrays (Pa, compression +) at points (x, y)."""
        d = self.depth(x, y, top)
        syy = self.syy + self.gyy * d
        sxx = self.k * syy if self.k is not None else self.sxx + self.gxx * d
        return sxx, syy, self.sxy + self.gxy * d

    def traction(self, x, y, nx, ny, top=None) -> tuple:
        """(sn, ts) on planes of unit normal (nx, ny) at (x, y): sn = n.S.n, ts = t.S.n with
        t = (-ny, nx) (Pa, compression +)."""
        sxx, syy, sxy = self.stress(x, y, top)
        tx, ty = sxx * nx + sxy * ny, sxy * nx + syy * ny
        return nx * tx + ny * ty, -ny * tx + nx * ty

    def run(self, model):
        """Give every live contact the traction of the field (``Model.set_contact_stress``)."""
        c = model.contacts
        if c.n == 0:
            return 0, "no contacts", {}
        xy = c.position(model.state.pos, model.state.rot)
        n = c.normal(model.state)
        top = None if self.surface is not None else model_top(model)
        sn, ts = self.traction(xy[:, 0], xy[:, 1], n[:, 0], n[:, 1], top)
        model.set_contact_stress(sn, ts)
        return 0, "set", {"contacts": int(c.n), "max_sn": float(sn.max()),
                          "min_sn": float(sn.min())}
