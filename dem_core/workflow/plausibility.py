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

Magnitudes no rock can have are errors, naming the value and the range taken as physical
(docs/bad-input.md):

- a contact stiffness kn or ks outside ``STIFFNESS`` = 1e4..1e17 Pa/m: kn ~ E / L, with E from
  1 MPa (a soft infill) to 1e12 Pa (stiffer than any rock) over blocks of 0.1 mm to 100 m
  (the scenes shipped here use about 1e8 to 1e12 Pa/m); far beyond it the time step under- or
  overflows (kn = 1e308 gave a ``ZeroDivisionError``);
- a g-level above ``G_LEVEL_MAX`` = 1e4 (geotechnical centrifuges reach about 1e3 g);
- an in-situ stress above ``STRESS_MAX`` = 1e10 Pa (the weight of about 400 km of rock; at
  the depth of the deepest mines, about 4 km, it is about 0.1 GPa) or a stress gradient
  above ``GRADIENT_MAX`` (the densest rock at ``G_LEVEL_MAX``).

On the built model (``stages.check_on_model``, before the first step): a gravity or in-situ
stress that would press the contacts together by more than a block's size
(``check_gravity_closure``, ``check_stress_closure``): no contact law holds that, and the run
would blow up at its first steps with a time-step message.

Units inside are SI (docs/scenes.md): Pa, kg/m^3, degrees.
"""
from __future__ import annotations

import warnings

import numpy as np
import shapely

from ..units import STANDARD_GRAVITY
from .water import WaterTable, surface_height

__all__ = ["ScenePlausibilityWarning", "unusual", "check_water_reaches", "check_no_gaps",
           "warn_unusual", "warn_slivers", "check_stiffness", "check_g_level", "check_stress",
           "check_gravity_closure", "check_stress_closure", "LIGHTEST", "FLATTEST",
           "WEAKEST_COHESION", "GAP", "SLIVER", "STIFFNESS", "G_LEVEL_MAX", "STRESS_MAX",
           "GRADIENT_MAX"]

LIGHTEST = 500.0            # kg/m^3
FLATTEST = 5.0              # deg
WEAKEST_COHESION = 1e3      # Pa, with a tensile strength of at least ...
STRONG_TENSION = 1e5        # Pa
GAP = 0.01                  # of the smaller region's size: regions closer than this must touch
SLIVER = 1e-4               # of the median block area
STIFFNESS = (1e4, 1e17)     # Pa/m: kn, ks outside are refused (module docstring)
G_LEVEL_MAX = 1e4           # g-levels above are refused
STRESS_MAX = 1e10           # Pa: in-situ stresses above are refused
GRADIENT_MAX = 2.3e4 * STANDARD_GRAVITY * G_LEVEL_MAX    # Pa/m: 23 t/m^3 at G_LEVEL_MAX
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


# ---------------------------------------------------------------------- magnitudes
def check_stiffness(materials: dict, where: str = "materials") -> None:
    """ValueError naming the first material (name -> ``Material``) whose kn or ks (Pa/m) is
    outside ``STIFFNESS``."""
    lo, hi = STIFFNESS
    for name, m in materials.items():
        for key in ("kn", "ks"):
            v = getattr(m, key)
            if not lo <= v <= hi:
                raise ValueError(f"{where}[{name!r}]: {key} = {v:.3g} Pa/m is not a contact "
                                 f"stiffness (taken as physical: {lo:.0e} to {hi:.0e} Pa/m, "
                                 f"about E / block size; the shipped scenes use about 1e+08 to "
                                 f"1e+12)")


def check_g_level(g_level, where: str) -> None:
    """ValueError for a g-level above ``G_LEVEL_MAX``."""
    if g_level > G_LEVEL_MAX:
        raise ValueError(f"{where}: g_level {g_level:.3g} is not a physical gravity (at most "
                         f"{G_LEVEL_MAX:g} g is taken; geotechnical centrifuges reach about "
                         f"1e3 g)")


def check_stress(values: dict, where: str) -> None:
    """ValueError for an in-situ stress (Pa) above ``STRESS_MAX`` or a gradient (Pa/m) above
    ``GRADIENT_MAX`` (``values``: name -> value, gradients named "g...")."""
    for name, v in values.items():
        limit, unit = (GRADIENT_MAX, "Pa/m") if name.startswith("g") else (STRESS_MAX, "Pa")
        if abs(v) > limit:
            raise ValueError(f"{where}: {name} = {v:.3g} {unit} is not a physical in-situ "
                             f"{'stress gradient' if unit == 'Pa/m' else 'stress'} (at most "
                             f"{limit:.3g} {unit} is taken; 1 km of rock is about 27 MPa)")


def _block_size(model) -> float:
    """The median block's size sqrt(area), m, over the active blocks."""
    area = np.asarray(model.blocks.area)[model.props.active > 0]
    return float(np.sqrt(np.median(area))) if area.size else 0.0


def _closure_error(where, cause, stress, kn, model) -> None:
    """ValueError when ``stress`` (Pa) on contacts of stiffness ``kn`` (Pa/m) closes them by
    more than a block's size (``_block_size``)."""
    size, closure = _block_size(model), stress / kn
    if kn > 0 and closure > size > 0:
        raise ValueError(f"{where}: {cause} would press the contacts together by about "
                         f"{closure:.3g} m ({stress:.3g} Pa / kn {kn:.3g} Pa/m), more than a "
                         f"block's size ({size:.3g} m): the load is far too large for these "
                         f"contacts (or kn far too small), and the run would blow up")


def check_gravity_closure(model, g_level, where: str) -> None:
    """ValueError when the model's weight at ``g_level``, rho g H at the base of a column of
    the model's height H, over the live contacts' median kn, closes a contact by more than a
    block's size."""
    c = model.contacts
    if c.n == 0 or g_level <= 0:
        return
    y = np.asarray(model.blocks.vertices)[:, 1]
    rho = float(np.max(model.props.mass / np.asarray(model.blocks.area)))
    stress = rho * g_level * STANDARD_GRAVITY * float(np.ptp(y))
    _closure_error(where, f"gravity of {g_level:.3g} g (rho g H = {stress:.3g} Pa at the "
                          f"base)", stress, float(np.median(c.kn[:c.n])), model)


def check_stress_closure(model, field, where: str, top=None) -> None:
    """ValueError when the in-situ ``field`` (``insitu.InSitu``; ``top``: the model's top
    polyline when its surface is None, ``insitu.model_top``) closes a live contact by more
    than a block's size: the largest normal stress over its contact's kn."""
    c = model.contacts
    if c.n == 0:
        return
    xy = c.position(model.state.pos, model.state.rot)
    n = c.normal(model.state)
    sn, _ = field.traction(xy[:, 0], xy[:, 1], n[:, 0], n[:, 1], top)
    k = int(np.argmax(np.abs(sn) / c.kn[:c.n]))
    _closure_error(where, f"an in-situ normal stress of {abs(sn[k]):.3g} Pa", abs(sn[k]),
                   float(c.kn[k]), model)
