"""Bishop's simplified method of slices: circular slip surfaces in a homogeneous c-phi slope.

No DOLFINx: plain numpy and scipy. Used to check the strength-reduction factor of safety of
`continuum_ref.ssr` and anywhere a quick limit-equilibrium number is wanted.

Method (Bishop 1955)
--------------------
The sliding mass between the ground surface y_g(x) and a circle (centre (xc, yc), radius R) is
cut into vertical slices of width b. Slice i has weight W = gamma b (y_g - y_b) at its middle
x, base height y_b, base inclination alpha with sin(alpha) = (xc - x) / R (positive where the
base descends in the direction of sliding), and pore pressure u = p(x, y_b) on its base. With
no interslice shear force, vertical equilibrium of each slice and moment equilibrium of the
mass about the centre give

    F = sum[(c b + (W - u b) tan(phi)) / m_alpha] / sum[W sin(alpha)],
    m_alpha = cos(alpha) + sin(alpha) tan(phi) / F,

solved by fixed-point iteration (F on the right from the previous iterate). The sliding mass
is everything between the ground and the circle's lower half, from its first to its last
crossing with the ground (a circle that cuts below the toe takes that soil with it). Slice
boundaries are equally spaced between those crossings, plus every ground vertex and inner
crossing (so ground and base are smooth over each slice and the midpoint rule converges as
b^2: 100 slices give F to 3e-5 relative, see tests/test_continuum_ssr.py).

Signs and units: c and p in Pa (p compression positive, e.g. `dem_core.workflow.water.WaterTable.
pressure`), phi in degrees, gamma in N/m^3 (the total, i.e. saturated where wet, unit weight),
lengths in m, x horizontal, y up. The slope may face either way: a slope that rises to the
right is mirrored internally and the circle is reported in the caller's coordinates.

Search: the circle is parametrised by its entry x (upslope end), exit x (downslope end) and
the sagitta of the arc below its chord. A grid over the three is evaluated and the best few
are refined with Nelder-Mead (scipy.optimize.minimize). Circles dipping below ``bottom`` (a
rigid base, as in a finite-element model) are excluded. A circle where m_alpha <= 0 on some
slice (a numerical artefact of Bishop's method at steep reverse bases) is rejected.

References: Bishop, A. W. (1955) The use of the slip circle in the stability analysis of
slopes, Geotechnique 5(1), 7-17; Duncan, Wright & Brandon (2014) Soil Strength and Slope
Stability, 2nd ed.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Circle", "BishopResult", "ground_polyline", "bishop_factor", "critical_circle"]


@dataclass(frozen=True)
class Circle:
    """A slip circle: centre (xc, yc) and radius r, m."""

    xc: float
    yc: float
    r: float


@dataclass
class BishopResult:
    """Critical circle of a search.

    Attributes
    ----------
    factor : float
        Bishop's factor of safety of the critical circle.
    circle : Circle
    entry, exit : float
        x (m) where the circle meets the ground upslope and downslope.
    evaluated : int
        Circles evaluated (grid and refinement).
    """

    factor: float
    circle: Circle
    entry: float
    exit: float
    evaluated: int


def ground_polyline(points) -> np.ndarray:
    """Check and return a ground surface as an (n, 2) float array: x non-decreasing (a vertical
    step is allowed, a fold is not), at least two points, all finite."""
    p = np.asarray(points, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 2 or not np.all(np.isfinite(p)):
        raise ValueError(f"ground must be [[x, y], ...] with >= 2 finite points, got {points!r}")
    if np.any(np.diff(p[:, 0]) < 0):
        raise ValueError("ground polyline folds back (x must not decrease along it)")
    if p[-1, 0] <= p[0, 0]:
        raise ValueError("ground polyline has no horizontal extent")
    return p


def _check_soil(cohesion, friction, unit_weight):
    if not (math.isfinite(cohesion) and cohesion >= 0):
        raise ValueError(f"cohesion={cohesion!r} must be >= 0 (Pa)")
    if not (math.isfinite(friction) and 0 <= friction < 90):
        raise ValueError(f"friction={friction!r} must be in [0, 90) degrees")
    if not (math.isfinite(unit_weight) and unit_weight > 0):
        raise ValueError(f"unit_weight={unit_weight!r} must be > 0 (N/m^3)")


def _facing_right(ground):
    """True if the ground falls from left to right (sliding towards +x)."""
    return ground[0, 1] >= ground[-1, 1]


def _mirror(ground, pore_pressure):
    """Ground and pore pressure in a frame where the slope faces right (x -> -x if needed)."""
    if _facing_right(ground):
        return ground, pore_pressure, 1.0
    flipped = np.column_stack([-ground[::-1, 0], ground[::-1, 1]])
    p = None if pore_pressure is None else (lambda x, y: pore_pressure(-np.asarray(x), y))
    return flipped, p, -1.0


def _slice_geometry(ground, circle, crossings, n_slices):
    """Middle x, width, ground and base heights of the slices between the first and last
    crossing (m); ground vertices and inner crossings are slice boundaries too."""
    x0, x1 = crossings[0], crossings[-1]
    inner = ground[(ground[:, 0] > x0) & (ground[:, 0] < x1), 0]
    edges = np.unique(np.concatenate([np.linspace(x0, x1, n_slices + 1), inner, crossings]))
    xm, b = 0.5 * (edges[1:] + edges[:-1]), np.diff(edges)
    yg = np.interp(xm, ground[:, 0], ground[:, 1])
    yb = circle.yc - np.sqrt(np.maximum(circle.r ** 2 - (xm - circle.xc) ** 2, 0.0))
    return xm, b, yg, yb


def _bishop_iteration(b, W, sin_a, cos_a, u, cohesion, tan_phi, tol=1e-10, max_iter=200):
    """F of one circle from its slices (module docstring); inf if it does not drive."""
    drive = np.sum(W * sin_a)
    if not drive > 0.0:
        return math.inf
    resist = cohesion * b + (W - u * b) * tan_phi
    F = 1.0
    for _ in range(max_iter):
        m_alpha = cos_a + sin_a * tan_phi / F
        if np.any(m_alpha <= 0.0):
            return math.inf
        F_new = np.sum(resist / m_alpha) / drive
        if abs(F_new - F) <= tol * F_new:
            return float(F_new)
        F = F_new
    return float(F)


def _factor(ground, circle, crossings, cohesion, friction, unit_weight, pore_pressure, n_slices):
    """Bishop F of the mass between the ground (facing right) and `circle`."""
    xm, b, yg, yb = _slice_geometry(ground, circle, crossings, n_slices)
    loaded = yg > yb
    if not loaded.any():
        return math.inf
    xm, b, yg, yb = xm[loaded], b[loaded], yg[loaded], yb[loaded]
    W = unit_weight * b * (yg - yb)
    sin_a = (circle.xc - xm) / circle.r
    cos_a = np.sqrt(np.maximum(1.0 - sin_a ** 2, 0.0))
    u = np.zeros_like(xm) if pore_pressure is None else np.broadcast_to(
        np.asarray(pore_pressure(xm, yb), dtype=np.float64), xm.shape)
    return _bishop_iteration(b, W, sin_a, cos_a, u, cohesion, math.tan(math.radians(friction)))


def _crossings(ground, circle):
    """Sorted x (m) where the lower half of `circle` crosses the ground; the first and last
    bound the sliding mass. None if the circle does not cut the ground or leaves the ground's
    extent while below it."""
    from scipy.optimize import brentq
    lo = max(circle.xc - circle.r, ground[0, 0])
    hi = min(circle.xc + circle.r, ground[-1, 0])
    if hi <= lo:
        return None

    def above(x):      # ground height above the circle's lower half
        yb = circle.yc - np.sqrt(np.maximum(circle.r ** 2 - (x - circle.xc) ** 2, 0.0))
        return np.interp(x, ground[:, 0], ground[:, 1]) - yb
    x = np.linspace(lo, hi, 2001)
    inside = above(x) > 0.0
    if not inside.any() or inside[0] or inside[-1]:
        return None
    flips = np.nonzero(inside[1:] != inside[:-1])[0]
    return np.array([brentq(above, x[k], x[k + 1]) for k in flips])


def bishop_factor(ground, circle, cohesion, friction, unit_weight, pore_pressure=None,
                  n_slices=100):
    """Bishop's simplified factor of safety of one slip circle (module docstring).

    Parameters
    ----------
    ground : (n, 2) array_like
        Ground surface polyline, x non-decreasing (m).
    circle : Circle
    cohesion : float
        c (Pa, effective where pore pressure is given).
    friction : float
        phi (degrees).
    unit_weight : float
        gamma (N/m^3), total.
    pore_pressure : callable p(x, y) -> Pa, optional
        Pore pressure on the slip surface (compression positive), e.g. WaterTable.pressure.
    n_slices : int
        Equal slices between entry and exit (ground vertices add boundaries).

    Returns
    -------
    float
        F (inf if the circle does not cut the ground or drives no mass).
    """
    _check_soil(cohesion, friction, unit_weight)
    ground = ground_polyline(ground)
    g, p, sign = _mirror(ground, pore_pressure)
    c = Circle(sign * circle.xc, circle.yc, circle.r)
    cuts = _crossings(g, c)
    if cuts is None:
        return math.inf
    return _factor(g, c, cuts, cohesion, friction, unit_weight, p, n_slices)


def _chord_circle(ground, xa, xb, q):
    """Circle through the ground at xa < xb whose arc sags q x chord length below the chord;
    None unless both ends are on its lower half (the slices are then single-valued)."""
    ya, yb = np.interp([xa, xb], ground[:, 0], ground[:, 1])
    dx, dy = xb - xa, yb - ya
    chord = math.hypot(dx, dy)
    if not (xb > xa and chord > 0 and q > 0):
        return None
    s = q * chord
    r = (s * s + 0.25 * chord * chord) / (2.0 * s)
    nx, ny = -dy / chord, dx / chord                    # unit normal pointing up
    circle = Circle(0.5 * (xa + xb) + (r - s) * nx, 0.5 * (ya + yb) + (r - s) * ny, r)
    return circle if circle.yc >= max(ya, yb) else None


def _lowest(circle, x0, x1):
    """Lowest point (m) of the circle's lower half between x0 and x1."""
    x = min(max(circle.xc, x0), x1)
    return circle.yc - math.sqrt(max(circle.r ** 2 - (x - circle.xc) ** 2, 0.0))


def _objective(ground, soil, pore_pressure, bottom, n_slices):
    """F as a function of (entry, exit, sag ratio) in the right-facing frame. The sliding mass
    is everything between the ground and the circle's lower half (its outermost crossings
    with the ground, which may lie beyond the chord's ends)."""
    def f(params):
        circle = _chord_circle(ground, *params)
        cuts = None if circle is None else _crossings(ground, circle)
        if cuts is None or (bottom is not None and
                            _lowest(circle, cuts[0], cuts[-1]) < bottom - 1e-9):
            return math.inf
        return _factor(ground, circle, cuts, *soil, pore_pressure, n_slices)
    return f


def _grid(x_lo, x_hi, n, sags):
    xs = np.linspace(x_lo, x_hi, n)
    return [(xa, xb, q) for i, xa in enumerate(xs) for xb in xs[i + 1:] for q in sags]


def critical_circle(ground, cohesion, friction, unit_weight, pore_pressure=None, bottom=None,
                    x_range=None, n_grid=24, sags=(0.03, 0.06, 0.1, 0.15, 0.2, 0.28, 0.36, 0.45),
                    n_best=4, n_slices=100):
    """Search the circle of least Bishop factor of safety (module docstring).

    Parameters
    ----------
    ground, cohesion, friction, unit_weight, pore_pressure, n_slices
        As in `bishop_factor`.
    bottom : float, optional
        Lowest elevation (m) a circle may reach (a rigid base).
    x_range : (float, float), optional
        Where entry and exit points may lie (default: the ground's extent).
    n_grid : int
        Grid points for entry and exit each; `sags`: arc depth / chord length values.
    n_best : int
        Grid minima refined by Nelder-Mead.

    Returns
    -------
    BishopResult
    """
    from scipy.optimize import minimize
    _check_soil(cohesion, friction, unit_weight)
    ground = ground_polyline(ground)
    g, p, sign = _mirror(ground, pore_pressure)
    lo, hi = (g[0, 0], g[-1, 0]) if x_range is None else sorted(sign * np.asarray(x_range))
    f = _objective(g, (cohesion, friction, unit_weight), p, bottom, n_slices)
    grid = _grid(lo, hi, n_grid, sags)
    values = np.array([f(x) for x in grid])
    if not np.isfinite(values).any():
        raise ValueError("no admissible slip circle: check the ground, x_range and bottom")
    best, evaluated = (math.inf, None), len(grid)
    step = (hi - lo) / (n_grid - 1)
    for k in np.argsort(values)[:n_best]:
        res = minimize(lambda z: min(f(z), 1e9), grid[k], method="Nelder-Mead",
                       bounds=[(lo, hi), (lo, hi), (1e-3, 0.5)],
                       options={"xatol": 1e-4 * step, "fatol": 1e-7, "maxiter": 2000,
                                "initial_simplex": _simplex(grid[k], step)})
        evaluated += res.nfev
        if res.fun < best[0]:
            best = (float(res.fun), res.x)
    c = _chord_circle(g, *best[1])
    cuts = _crossings(g, c)
    xa, xb = cuts[0], cuts[-1]
    entry, exit_ = (xa, xb) if sign > 0 else (-xa, -xb)
    return BishopResult(best[0], Circle(sign * c.xc, c.yc, c.r), entry, exit_, evaluated)


def _simplex(x, step):
    """Starting simplex of one grid step around a grid point (entry, exit, sag ratio)."""
    x = np.asarray(x, dtype=float)
    d = np.diag([0.5 * step, 0.5 * step, 0.3 * x[2]])
    return np.vstack([x, x + d])
