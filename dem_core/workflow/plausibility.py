"""Physical plausibility of a scene, checked when a scene file is read (``Scene.from_dict``).

What cannot be meant is an error (ValueError): a water table below the whole model, which
puts no water anywhere (a depth given as a negative level, a level in the wrong datum).

Two regions that almost touch are an error too: a gap narrower than ``GAP`` = 1 % of the
smaller region's size between regions that do not touch (an edge meant to be shared, given
with coordinates a little apart, leaves the blocks on either side without contacts).

What is unusual but possible is a one-line ``ScenePlausibilityWarning`` each, naming the value
and the likely slip; ``run-scene --strict`` turns them into errors:

- a water table above the ground surface: the water outside the slope is a reservoir pressing
  on the face, which is rarely meant;
- a density under ``LIGHTEST`` = 500 kg/m^3 (rock is 1,800-3,000: t/m^3 or g/cm^3 given?);
- a friction angle above 0 and under ``FLATTEST`` = 5 deg (a tangent or radians given? 0 is
  a frictionless surface, e.g. a lab platen, and is taken as meant);
- a cohesion under ``WEAKEST_COHESION`` = 1 kPa on a material whose tensile strength is at
  least 0.1 MPa (kPa given where Pa is meant?).

And, when the blocks are built (``build_model``), blocks under ``SLIVER`` = 1e-4 of the
median block area: each one sets the time step (``Model(mass_scaling=True)`` lifts that).

Units inside are SI (docs/scenes.md): Pa, kg/m^3, degrees.
"""
from __future__ import annotations

import warnings

import numpy as np
import shapely

from .water import WaterTable, surface_height

__all__ = ["ScenePlausibilityWarning", "unusual", "check_water_reaches", "check_no_gaps",
           "warn_unusual", "warn_slivers", "LIGHTEST", "FLATTEST", "WEAKEST_COHESION", "GAP",
           "SLIVER"]

LIGHTEST = 500.0            # kg/m^3
FLATTEST = 5.0              # deg
WEAKEST_COHESION = 1e3      # Pa, with a tensile strength of at least ...
STRONG_TENSION = 1e5        # Pa
GAP = 0.01                  # of the smaller region's size: regions closer than this must touch
SLIVER = 1e-4               # of the median block area
_SAMPLES = 201              # abscissae at which the ground and a water table are compared


class ScenePlausibilityWarning(UserWarning):
    """A scene value that is possible but unusual enough to be a slip (module docstring)."""


def _ground(scene):
    """(x (n,), top y (n,), lowest y) of the model's regions: the ground surface sampled over
    the model's width."""
    rock = shapely.union_all([r.polygon() for r in scene.geometry.regions])
    x0, y0, x1, y1 = rock.bounds
    xs = np.linspace(x0, x1, _SAMPLES)[1:-1]
    top = np.array([shapely.intersection(rock, shapely.LineString([(x, y0 - 1), (x, y1 + 1)]))
                    .bounds[3] for x in xs])
    return xs, top, y0


def _water_stages(scene):
    return [(i, st) for i, st in enumerate(scene.stages)
            if isinstance(st, WaterTable) and st.surface is not None]


def check_water_reaches(scene) -> None:
    """ValueError for a water table wholly below the model (no water anywhere)."""
    stages = _water_stages(scene)
    if not stages:
        return
    xs, _, lowest = _ground(scene)
    for i, st in stages:
        level = surface_height(st.surface, xs)
        if np.all(level <= lowest):
            raise ValueError(f"stage {i} (water): the water table (at most {level.max():g} m) "
                             f"is below the whole model (lowest point y = {lowest:g} m), so "
                             f"it puts no water anywhere: a depth given where a level is "
                             f"meant?")


def check_no_gaps(scene) -> None:
    """ValueError for two regions closer than ``GAP`` of the smaller one's size that do not
    touch (a gap of round-off, up to 1e-9 of the model's size, counts as touching, as for
    the monitoring points: the Lornex and common-toppling scenes share edges to 1e-14 m)."""
    regions = scene.geometry.regions
    polys = [r.polygon() for r in regions]
    x0, y0, x1, y1 = shapely.union_all(polys).bounds
    touch = 1e-9 * max(1.0, float(np.hypot(x1 - x0, y1 - y0)))   # round-off: they touch
    for i in range(len(polys)):
        for j in range(i + 1, len(polys)):
            gap = polys[i].distance(polys[j])
            size = min(np.sqrt(polys[i].area), np.sqrt(polys[j].area))
            if touch < gap < GAP * size:
                raise ValueError(f"regions {regions[i].name!r} and {regions[j].name!r} are "
                                 f"{gap:.3g} m apart, under {GAP:.0%} of the smaller one's "
                                 f"size: a gap where an edge was meant to be shared? (no "
                                 f"contact crosses it)")


def warn_slivers(blocks) -> None:
    """A ``ScenePlausibilityWarning`` for blocks under ``SLIVER`` of the median area."""
    area = np.asarray(blocks.area, dtype=float)
    if not area.size:
        return
    small = np.flatnonzero(area < SLIVER * np.median(area))
    if small.size:
        k = small[np.argmin(area[small])]
        x, y = blocks.centroid[k]
        warnings.warn(f"{small.size} block(s) under {SLIVER:g} of the median block area "
                      f"(smallest {area[k]:.3g} m^2 at ({x:.4g}, {y:.4g}) m): each sets the "
                      f"time step; Model(mass_scaling=True) lifts that",
                      ScenePlausibilityWarning, stacklevel=3)


def unusual(scene) -> list:
    """One line per unusual value of ``scene`` (module docstring)."""
    out = []
    density = np.atleast_1d(np.asarray(scene.density, dtype=float))
    if density.min() < LIGHTEST:
        out.append(f"density {density.min():g} kg/m^3 is below {LIGHTEST:g}: rock is "
                   f"1,800-3,000 kg/m^3 (t/m^3 given?)")
    for name, m in scene.materials.items():
        if 0 < m.friction < FLATTEST:            # 0: a frictionless surface, meant
            out.append(f"materials[{name!r}]: friction {m.friction:g} deg is below "
                       f"{FLATTEST:g} deg (a tangent or radians given?)")
        if 0 < m.cohesion < WEAKEST_COHESION and m.tensile_strength >= STRONG_TENSION:
            out.append(f"materials[{name!r}]: cohesion {m.cohesion:g} Pa is below "
                       f"{WEAKEST_COHESION:g} Pa while the tensile strength is "
                       f"{m.tensile_strength:g} Pa (kPa given where Pa is meant?)")
    out += _reservoirs(scene)
    return out


def _reservoirs(scene) -> list:
    stages = _water_stages(scene)
    if not stages:
        return []
    xs, top, _ = _ground(scene)
    out = []
    for i, st in stages:
        above = surface_height(st.surface, xs) - top
        k = int(np.argmax(above))
        if above[k] > 1e-6 * max(1.0, float(np.ptp(top))):
            out.append(f"stage {i} (water): the water table is {above[k]:.3g} m above the "
                       f"ground at x = {xs[k]:g} m: the water outside the slope presses on "
                       f"the face as a reservoir")
    return out


def warn_unusual(scene) -> None:
    """Each line of ``unusual`` as a ``ScenePlausibilityWarning``."""
    for line in unusual(scene):
        warnings.warn(line, ScenePlausibilityWarning, stacklevel=3)
