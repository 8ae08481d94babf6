"""Highwood Pass site 1, flexural buckling of beds parallel to a natural slope face (Hu & Cruden
1993; thesis section 5.3.3, table 5.5).

Geometry (m), origin at the bottom-left corner of the model, the slope facing +x, so the beds,
which dip with the face, are ``dip_direction="right"``:

- a ``slope_height`` = 100 m face dipping ``face_dip`` = 84 degrees (thesis: "about 100 m",
  beds and face at 84), the beds parallel to it through the whole model (they continue below
  the toe level). **Assumptions** (figs 5.13-5.14 are not in the text; no dimension other than
  the height is given): ``base`` = 10 m of rock under the toe level, ``toe_length`` = 10 m of
  toe bench, ``crest_length`` = 30 m of crest behind the face's top edge;
- the surface quartzite: ``quartzite_beds`` beds parallel to the face, from the face inwards.
  The thesis gives only the range "0.4-1.2 m"; **assumption**: five beds 0.4, 0.6, 0.8, 1.0 and
  1.2 m thick (the range in even steps, the thinnest at the face, 4.0 m in all);
- the inner limestone: beds ``limestone_bed`` = 0.7 m thick cut by cross joints perpendicular
  to them every ``limestone_cross`` = 0.4 m (thesis: "kept constant at 0.7 m", cross joints at
  0.4 m), over ``limestone_depth`` (normal) behind the quartzite. **Assumption**: 10 m; the
  rock behind it (``back``) and the rock in front of the face plane under the toe bench
  (``bench``) are single elastic blocks (they touch the fixed base, so they are held: the
  buckle's mechanism lies in the surface beds, which slide on the limestone);
- **leave out what the scene does not need**: Voronoi flaws (block edge ``edge_length``, thesis
  0.2 m) fill the quartzite beds only between ``zone_bottom`` and ``zone_top`` (m above the toe
  level; default -5 to 60 m): the thesis's buckles form at the toe and in the middle of the
  face (figs 5.15, 5.16; no significant fracturing at the crest, fig 5.20). Above and below
  the zone each bed is cut across (perpendicular to the bedding) every ``cut_spacing`` = 2 m by
  lines of the same intact rock (flaw contacts of the same strength, one per cut), so the beds
  stay continuous and breakable there, but cannot buckle in a wavelength shorter than 2 m;
- boundaries: the blocks touching the base fixed, those touching the sides on rollers (x held);
- monitoring points on the face, 0.1 m inside the outer bed: ``B`` 5 m above the toe level
  (thesis: point B, the toe), ``M`` at mid-height and ``A`` 2 m below the crest (thesis:
  point A, the crest).

Materials (table 5.5): joints (bedding, limestone cross joints, the bedding planes between the
quartzite beds) friction 30, c 0, T 0, kn 10, ks 5 GPa/m; quartzite flaws friction 30, c 5 MPa,
T 1.6 MPa, kn 400, ks 200 GPa/m; blocks E 20 GPa, unit weight 25 kN/m3. **Assumption**:
Poisson's ratio 0.25 (not given). The apertures (1 and 0.1 mm) are hydraulic and the slope is
dry (thesis), so they are not used. The intact quartzite is one material key, ``QUARTZITE``
("*:q*": the flaws of every bed part and the boundaries between parts of one bed), so one
strength schedule lowers all of it; the boundaries between different beds are bedding joints.

Stages (``stages``): the thesis's initialisation (thesis 5.2; ``dem_core.workflow.insitu.
strong_then_real``: the quartzite made 1000 times stronger, gravity, the in-situ stress, solved,
the real strength given back), then T of the quartzite lowered step by step until the slope
fails (``strength_schedule``). In-situ stress: **assumption** (the thesis gives only the ratio
k = sh / sv): the geostatic field of the ground before the valley was cut, its surface flat at
the crest level, sv = rho g depth, sh = k sv; the face exists from the start, so the first
solve releases the face's horizontal stress, as an instant excavation of the valley would (the
unloading that Stacey et al. 2003 relate to tension in slopes at high k). Conventional mode
(the thesis's conventional UDEC): the quartzite's flaws are unbreakable.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np
from shapely.geometry import Polygon

from dem_core.geometry import GeometrySpec, JointSet, Region, Voronoi, slope_profile
from dem_core.workflow.insitu import InSitu
from dem_core.contact.materials import Material
from dem_core.workflow.scene import Boundary, Scene
from dem_core.workflow.stages import ChangeMaterial, Gravity, Solve, StrengthSchedule
from dem_core.units import STANDARD_GRAVITY

from . import old_param_names

UNIT_WEIGHT = 25e3                      # N/m3
DENSITY = UNIT_WEIGHT / STANDARD_GRAVITY            # kg/m3
QUARTZITE = "*:q*"                      # material key of the intact quartzite (docstring)
STRONG = 1e3                            # initialisation: quartzite T and c times this
GROUPS = {"base": {"touching": "bottom"}, "left side": {"touching": "left"},
          "right side": {"touching": "right"},
          "side walls": {"union": ["left side", "right side"]},
          "sides": {"minus": ["side walls", "base"]}}
BOUNDARIES = [Boundary("base"), Boundary("sides", x=True, y=False, rotation=False)]


@old_param_names
@dataclass(frozen=True)
class HighwoodParams:
    """The scene's parameters (SI units, angles in degrees); defaults are the thesis's run
    with the assumptions of the module docstring."""

    slope_height: float = 100.0
    face_dip: float = 84.0
    base: float = 10.0
    toe_length: float = 10.0
    crest_length: float = 30.0
    quartzite_beds: tuple = (0.4, 0.6, 0.8, 1.0, 1.2)
    limestone_bed: float = 0.7
    limestone_cross: float = 0.4
    limestone_depth: float = 10.0
    edge_length: float = 0.2
    zone_bottom: float = -5.0
    zone_top: float = 60.0
    cut_spacing: float = 2.0
    relax_iterations: int = 20
    seed: int = 1
    flaw_tensile_strength: float = 1.6e6
    flaw_cohesion: float = 5.0e6
    flaw_friction: float = 30.0
    flaw_kn: float = 400e9
    flaw_ks: float = 200e9
    joint_friction: float = 30.0
    joint_kn: float = 10e9
    joint_ks: float = 5e9
    block_E: float = 20e9
    block_nu: float = 0.25
    stress_ratio: float = 1.0
    conventional: bool = False

    def __post_init__(self):
        _check(self)

    def with_(self, **changes) -> "HighwoodParams":
        return replace(self, **changes)


_POSITIVE = ("slope_height", "base", "toe_length", "crest_length", "limestone_bed",
             "limestone_cross", "limestone_depth", "edge_length", "cut_spacing", "flaw_kn",
             "flaw_ks", "joint_kn", "joint_ks", "block_E")


def _check(p: HighwoodParams):
    """ValueError naming the first value out of range (before any compute)."""
    for name in _POSITIVE:
        v = getattr(p, name)
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"HighwoodParams.{name} = {v!r} must be finite and > 0")
    for name in ("flaw_tensile_strength", "flaw_cohesion", "stress_ratio"):
        v = getattr(p, name)
        if not (math.isfinite(v) and v >= 0):
            raise ValueError(f"HighwoodParams.{name} = {v!r} must be finite and >= 0")
    for name in ("face_dip", "flaw_friction", "joint_friction"):
        v = getattr(p, name)
        if not 0 < v < 90:
            raise ValueError(f"HighwoodParams.{name} = {v!r} must be in (0, 90) degrees")
    if not 0 <= p.block_nu < 0.5:
        raise ValueError(f"HighwoodParams.block_nu = {p.block_nu!r} must be in [0, 0.5)")
    if not p.quartzite_beds or min(p.quartzite_beds) <= 0:
        raise ValueError(f"HighwoodParams.quartzite_beds = {p.quartzite_beds!r} must be "
                         "thicknesses > 0 (m)")
    if not -p.base < p.zone_bottom < p.zone_top <= p.slope_height:
        raise ValueError(f"HighwoodParams zone_bottom = {p.zone_bottom!r}, zone_top = "
                         f"{p.zone_top!r} must satisfy -base < zone_bottom < zone_top <= "
                         f"slope_height (m above the toe level)")
    # the quartzite and limestone bands span depth / sin(dip) horizontally at every level
    depth = (sum(p.quartzite_beds) + p.limestone_depth) / math.sin(math.radians(p.face_dip))
    if depth >= p.crest_length:
        raise ValueError(f"HighwoodParams.crest_length = {p.crest_length!r} m leaves no rock "
                         f"behind the quartzite and limestone ({depth:.1f} m horizontally)")


def toe(p: HighwoodParams) -> tuple:
    """The toe of the face (x, y), m."""
    run = p.slope_height / math.tan(math.radians(p.face_dip))
    return p.crest_length + run, p.base


def face(p: HighwoodParams):
    """The free face as ((x_toe, y_toe), (x_crest, y_crest)), m."""
    tx, ty = toe(p)
    return (tx, ty), (p.crest_length, p.base + p.slope_height)


def slope_region(p: HighwoodParams) -> Region:
    """The whole section as one Region (what the continuum meshes)."""
    return slope_profile(p.slope_height, p.face_dip, p.crest_length, p.toe_length, p.base,
                         name="rock")


def profile(p: HighwoodParams = None) -> list:
    """The slope section (m), counter-clockwise from the bottom-left corner."""
    return [tuple(map(float, xy)) for xy in slope_region(p or HighwoodParams()).exterior]


def _inward(p):
    """Unit normal of the face pointing into the slope, and the unit vector up the dip."""
    t = math.radians(p.face_dip)
    return np.array([-math.sin(t), -math.cos(t)]), np.array([-math.cos(t), math.sin(t)])


def _band(p, d0, d1) -> Polygon:
    """The strip between normal depths d0 and d1 (m) behind the face plane (infinite along
    the dip; clip it to the model)."""
    n, u = _inward(p)
    o, far = np.asarray(toe(p)), 10.0 * (p.slope_height + p.base)
    return Polygon([o + d0 * n - far * u, o + d0 * n + far * u, o + d1 * n + far * u,
                    o + d1 * n - far * u])


def _level(p, y0, y1) -> Polygon:
    """The horizontal strip between absolute levels y0 and y1 (m)."""
    w = 10.0 * (p.crest_length + p.toe_length + p.slope_height)
    return Polygon([(-w, y0), (w, y0), (w, y1), (-w, y1)])


def _add(out, name, geom, p):
    pieces = [g for g in getattr(geom, "geoms", [geom]) if g.geom_type == "Polygon"
              and g.area > 1e-6]
    if len(pieces) != 1:
        raise ValueError(f"highwood: region {name!r} falls into {len(pieces)} pieces; check "
                         f"the dimensions of {p!r}")
    ring = np.asarray(pieces[0].exterior.coords)[:-1]
    out.append(Region(name, ring.tolist()))


def regions(p: HighwoodParams) -> list:
    """bench (in front of the face plane), the quartzite beds q1 (outer) .. qN, each split into
    the flaw zone (``qI``) and the parts below (``qI_low``, if the zone starts above the base)
    and above it (``qI_up``, if it ends below the crest), the limestone band (``lime``) and
    the rock behind it (``back``)."""
    rock = slope_region(p).polygon()
    y_lo, y_hi = p.base + p.zone_bottom, p.base + p.zone_top
    top = p.base + p.slope_height
    out = []
    _add(out, "bench", rock.intersection(_band(p, -1e4, 0.0)), p)
    d = 0.0
    for i, t in enumerate(p.quartzite_beds, 1):
        bed = rock.intersection(_band(p, d, d + t))
        _add(out, f"q{i}", bed.intersection(_level(p, y_lo, y_hi)), p)
        if y_lo > 1e-9:
            _add(out, f"q{i}_low", bed.intersection(_level(p, -1.0, y_lo)), p)
        if y_hi < top - 1e-9:
            _add(out, f"q{i}_up", bed.intersection(_level(p, y_hi, top + 1.0)), p)
        d += t
    _add(out, "lime", rock.intersection(_band(p, d, d + p.limestone_depth)), p)
    _add(out, "back", rock.intersection(_band(p, d + p.limestone_depth, 1e4)), p)
    return out


def _bed_of(name):
    """The quartzite bed number of a region name (None for the other rock)."""
    return int(name[1:].split("_")[0]) if name.startswith("q") else None


def geometry(p: HighwoodParams) -> GeometrySpec:
    regs = regions(p)
    names = [r.name for r in regs]
    outside = [n for n in names if n.startswith("q") and "_" in n]
    n, _ = _inward(p)
    origin = tuple(map(float, toe(p) + (sum(p.quartzite_beds)) * n))
    cross_dip = 90.0 - p.face_dip          # perpendicular to the beds, dipping the other way
    joints = [JointSet("bedding", p.face_dip, p.limestone_bed, dip_direction="right",
                       origin=origin, regions=["lime"]),
              JointSet("cross", cross_dip, p.limestone_cross, dip_direction="left",
                       origin=origin, regions=["lime"])]
    if outside:
        joints.append(JointSet("qcut", cross_dip, p.cut_spacing, persistence=0.0,
                               dip_direction="left", origin=toe(p), regions=outside))
    vor = {r.name: Voronoi(edge_length=p.edge_length, relax_iterations=p.relax_iterations,
                           seed=p.seed + i)
           for i, r in enumerate(regs) if r.name.startswith("q") and "_" not in r.name}
    return GeometrySpec(regs, joint_sets=joints, voronoi=vor)


def materials(p: HighwoodParams) -> dict:
    """Table 5.5 (module docstring): the quartzite key ``QUARTZITE`` (its flaws, the cuts and
    the boundaries between parts of one bed) and, by exact name, the joints: the limestone's
    sets and every other region boundary (bedding planes)."""
    flaw = Material(kn=p.flaw_kn, ks=p.flaw_ks, tensile_strength=p.flaw_tensile_strength,
                    cohesion=p.flaw_cohesion, friction=p.flaw_friction,
                    breakable=not p.conventional)     # conventional: intact rock is glued
    joint = Material(kn=p.joint_kn, ks=p.joint_ks, tensile_strength=0.0, cohesion=0.0,
                     friction=p.joint_friction)
    # exact names for everything but the quartzite: a pattern such as "flaw:*" would be longer
    # than QUARTZITE and win over it (``materials.material_for``)
    out = {QUARTZITE: flaw, "joint:bedding": joint, "joint:cross": joint}
    names = sorted(r.name for r in regions(p))
    for a in ("bench", "lime", "back"):     # no flaws there (no Voronoi, persistent joints)
        out[f"flaw:{a}"] = replace(flaw, breakable=False)
    for a in names:                  # either order: boundaries are named in region order
        for b in names:
            if a != b and (_bed_of(a) is None or _bed_of(a) != _bed_of(b)):
                out[f"boundary:{a}|{b}"] = joint
    return out


def monitoring_points(p: HighwoodParams = None) -> dict:
    """Points B (5 m above the toe level), M (mid-height) and A (2 m below the crest) on the
    face, 0.1 m inside the outer bed, m."""
    p = p or HighwoodParams()
    n, u = _inward(p)
    o = np.asarray(toe(p)) + 0.1 * n
    along = 1.0 / math.sin(math.radians(p.face_dip))       # m along the dip per m of height
    return {k: tuple(map(float, o + h * along * u)) for k, h in
            (("B", 5.0), ("M", 0.5 * p.slope_height), ("A", p.slope_height - 2.0))}


def stages(p: HighwoodParams, values, refine_to=None, max_steps=20_000, ratio=1e-5,
           failure_displacement=0.5, init_steps=100_000) -> list:
    """Initialisation (strong quartzite, gravity, the in-situ field with k =
    ``p.stress_ratio``, solved; real strength back; module docstring), then the quartzite's T
    lowered through ``values`` (Pa), bisected to ``refine_to``; a level fails when one of the
    points A, M, B moves more than ``failure_displacement`` (m) in it or keeps moving
    (``dem_core.workflow.limit``, watching the points)."""
    top = p.base + p.slope_height
    strong = {"tensile_strength": STRONG * p.flaw_tensile_strength,
              "cohesion": STRONG * p.flaw_cohesion}
    real = {"tensile_strength": p.flaw_tensile_strength, "cohesion": p.flaw_cohesion}
    return [ChangeMaterial(QUARTZITE, strong), Gravity(1.0),
            InSitu.geostatic(DENSITY, p.stress_ratio, surface=top),
            Solve(ratio=ratio, max_steps=init_steps), ChangeMaterial(QUARTZITE, real),
            StrengthSchedule(QUARTZITE, "tensile_strength", tuple(float(v) for v in values),
                             refine_to=refine_to, ratio=ratio, max_steps=max_steps,
                             failure_displacement=failure_displacement,
                             watch=tuple(monitoring_points(p)))]


def scene(p: HighwoodParams, stage_list=()) -> Scene:
    """The scene as data: geometry, materials, fixed base and rollers, points A, M, B, local
    damping 0.8 with mass scaling (quasi-static, as UDEC's default), and ``stage_list``."""
    # the library's contact model: edge elements on the rigid blocks (2026-12-01; end
    # springs before: solver {"edge_elements": false}, docs/comparisons.md)
    solver = {"new_contact_material": "joint:bedding", "mass_scaling": True, "damping": 0.8}
    return Scene(geometry(p), materials(p), density=DENSITY, block_E=p.block_E,
                 block_nu=p.block_nu, groups=GROUPS, boundaries=BOUNDARIES,
                 points=monitoring_points(p), stages=list(stage_list), solver=solver,
                 name="highwood")


def params_dict(p: HighwoodParams) -> dict:
    """Plain data of ``p`` (a sweep member's ``params``)."""
    return {f.name: getattr(p, f.name) for f in fields(p)}
