"""Underdip toppling of a bedded sandstone slope after Cruden & Hu (1994) (thesis 5.2.1, table
5.1, figs 5.3-5.5).

Geometry (m), origin at the bottom-left corner, the slope facing +x; every assumption the
thesis's figure 5.3 forces (it gives only the height and the two dips) is stated here:

- a 75 m slope with a 61 degree face (thesis); **assumption**: ``base`` = 15 m of rock under
  the toe level, ``crest_length`` = 45 m of crest behind the face and ``toe_length`` = 20 m of
  toe bench in front of it (the model's sides are then more than twice the zone of flaws away
  from the face);
- one persistent bedding set dipping 80 degrees in the face's direction (``dip_direction``
  "right": steeper than the face, so every bed is cut by the face: underdip), 0.75 m apart
  (normal), cutting the whole model (base included), one bed joint through the toe;
- non-uniform beds (thesis fig 5.5 names them, gives no numbers): **assumption** the same set
  with each joint shifted normal to itself by a uniform random amount within +-``jitter`` x
  spacing / 2 (``jitter`` 0.8: beds 0.15-1.35 m thick, the mean still 0.75 m;
  ``dem_core.geometry.JointSet.jitter``);
- the flaws: "generated inside each bed to make the polygonal shape of the blocks more
  brick-like" (thesis). UDEC-DM's flaws are a Voronoi tessellation, so **choice**: Voronoi
  cells of edge ``edge_length`` (1.5 m = two bed thicknesses by default and in the quick
  variant, 1.0 m in the full variant; the thesis gives no size) split by the bed joints: each
  bed is cut into polygonal bricks one bed thick and 1-2 m long whose ends are staggered from
  bed to bed by the tessellation itself (a set of cross cuts with persistence 0 would put the
  brick ends of all beds on the same straight lines, i.e. a continuous cross plane of flaws the
  thesis does not have, unless every bed were its own region);
- **leave out what a scene does not need**: the flaws fill only the zone within ``zone_depth``
  (25 m, normal to the face) of the face, between the toe and crest levels
  (``zone_polygon_along_face``): the thesis's toppled zone is about 15 m thick (and Cruden &
  Hu's field topples too), so 25 m holds it with 10 m to spare; the toppled-zone thickness this
  model measures is checked against the zone depth (a zone that fails up to its back would say
  the zone is too thin; measured with 1.0 m cells: the failed mass 16 m deep in the 25 m zone
  and 10 m in a 35 m zone, failing at the same cohesion; with 1.5 m cells it fills the zone). Behind the zone and under the toe level the beds are joint-bounded
  columns without flaws, each running down to the model's base (so fixed there: the base rock
  is not part of the mechanism; rigid columns do not bend as UDEC's zoned blocks would, so the
  zone's back is propped); the interface between the zone and that rock is flaw material
  (``boundary:zone|rock``) kept at the table's strength (the schedules lower ``flaw:zone``);
- boundaries: the blocks touching the base fixed, rollers on both sides (as the centrifuge
  scenes, ``CENTRIFUGE_BOUNDARIES``);
- points: ``crest`` (2 m behind the crest edge, 1 m deep), ``face`` (mid-face, 1 m inside),
  ``toe`` (on the face 3 m above the toe, 1 m inside).

Materials (table 5.1): bedding friction 25 (cohesion and tension 0); flaws T 60 kPa, cohesion
0.6 MPa, friction 30; kn 1 GPa/m, ks 0.1 GPa/m for both. **Assumptions** (not in the thesis):
density 2500 kg/m3 (sandstone), blocks E 10 GPa, nu 0.25 (the contacts, at 1 GPa/m on 0.75-1.5 m
blocks, are 5-10 times softer than the blocks, so E barely matters). Conventional mode (the
thesis's conventional UDEC): the same bricks with unbreakable flaws.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np
from shapely.geometry import Polygon

from dem_core.geometry import GeometrySpec, JointSet, Region, Voronoi, slope_profile
from dem_core.geometry import zone_polygon_along_face
from dem_core.contact.materials import Material
from dem_core.workflow.scene import Scene

from . import CENTRIFUGE_BOUNDARIES, CENTRIFUGE_GROUPS, old_param_names

HEIGHT, FACE_DIP, BED_DIP = 75.0, 61.0, 80.0      # m, degrees, degrees (thesis)
INTERFACE = "boundary:zone|rock"                # the zone of flaws against the rock behind it


@old_param_names
@dataclass(frozen=True)
class UnderdipParams:
    """The scene's parameters (SI units, angles in degrees); defaults are the thesis's run
    (table 5.1) with the geometry assumptions of the module docstring."""

    bed_spacing: float = 0.75
    jitter: float = 0.0                  # 0: uniform beds; 0.8: the non-uniform variant
    edge_length: float = 1.5
    relax_iterations: int = 20
    seed: int = 1
    zone_depth: float = 25.0
    base: float = 15.0
    crest_length: float = 45.0
    toe_length: float = 20.0
    bed_friction: float = 25.0
    flaw_tensile_strength: float = 60e3
    flaw_cohesion: float = 0.6e6
    flaw_friction: float = 30.0
    kn: float = 1e9
    ks: float = 0.1e9
    density: float = 2500.0
    block_E: float = 10e9
    block_nu: float = 0.25
    conventional: bool = False

    def __post_init__(self):
        for f in fields(self):
            v = getattr(self, f.name)
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                continue
            if not math.isfinite(v) or v < 0:
                raise ValueError(f"UnderdipParams.{f.name} must be finite and >= 0, got {v}")
        for name in ("bed_spacing", "edge_length", "zone_depth", "kn", "ks", "density",
                     "block_E"):
            if getattr(self, name) <= 0:
                raise ValueError(f"UnderdipParams.{name} must be > 0, got "
                                 f"{getattr(self, name)}")
        if not self.jitter < 1.0:
            raise ValueError(f"UnderdipParams.jitter must be in [0, 1), got {self.jitter}")
        for name in ("bed_friction", "flaw_friction"):
            if not getattr(self, name) < 90.0:
                raise ValueError(f"UnderdipParams.{name} must be < 90 degrees, got "
                                 f"{getattr(self, name)}")
        if self.zone_depth >= self.crest_length * math.sin(math.radians(FACE_DIP)):
            raise ValueError(f"UnderdipParams.zone_depth {self.zone_depth} m: the zone would "
                             f"reach the model's back (crest_length {self.crest_length} m)")

    def with_(self, **changes) -> "UnderdipParams":
        return replace(self, **changes)


def _run() -> float:
    return HEIGHT / math.tan(math.radians(FACE_DIP))


def slope_region(p: UnderdipParams) -> Region:
    """The whole section as one Region (what the continuum meshes)."""
    return slope_profile(HEIGHT, FACE_DIP, crest_length=p.crest_length,
                         toe_length=p.toe_length, base_thickness=p.base, name="rock")


def profile(p: UnderdipParams | None = None) -> list:
    """The slope section (m), counter-clockwise from the bottom-left corner."""
    return [tuple(map(float, xy)) for xy in slope_region(p or UnderdipParams()).exterior]


def face(p: UnderdipParams | None = None):
    """The free face as ((x_toe, y_toe), (x_crest, y_crest)), m."""
    p = p or UnderdipParams()
    return ((p.crest_length + _run(), p.base), (p.crest_length, p.base + HEIGHT))


def face_normal_depth(p: UnderdipParams, x, y) -> np.ndarray:
    """Normal distance (m) of points behind the face's line, positive into the rock."""
    (tx, ty), _ = face(p)
    t = math.radians(FACE_DIP)
    return (tx - np.asarray(x)) * math.sin(t) - (np.asarray(y) - ty) * math.cos(t)


def monitoring_points(p: UnderdipParams | None = None) -> dict:
    """Points crest, face and toe, m (module docstring)."""
    p = p or UnderdipParams()
    (tx, ty), (cx, cy) = face(p)
    t = math.radians(FACE_DIP)
    inward = np.array([-math.sin(t), -math.cos(t)])    # unit normal into the rock

    def on_face(height):
        return np.array([tx, ty]) + height * np.array([-1 / math.tan(t), 1.0])
    return {"crest": (cx - 2.0, cy - 1.0),
            "face": tuple(map(float, on_face(0.5 * HEIGHT) + inward)),
            "toe": tuple(map(float, on_face(3.0) + inward))}


def bed_set(p: UnderdipParams) -> JointSet:
    """The bedding: persistent, dipping with the face, one joint through the toe."""
    return JointSet("beds", BED_DIP, p.bed_spacing, dip_direction="right", origin=face(p)[0],
                    jitter=p.jitter, seed=p.seed)


def regions(p: UnderdipParams) -> list:
    """The zone of flaws along the face and the rest of the rock (module docstring)."""
    rock = slope_region(p)
    zone = Polygon(zone_polygon_along_face(rock, p.zone_depth))
    rest = rock.polygon().difference(zone)
    if rest.geom_type != "Polygon":
        raise ValueError(f"zone_depth {p.zone_depth} m splits the rock behind it in parts")
    return [Region("zone", list(zone.exterior.coords)[:-1]),
            Region("rock", list(rest.exterior.coords)[:-1])]


def geometry(p: UnderdipParams) -> GeometrySpec:
    vor = {"zone": Voronoi(edge_length=p.edge_length, relax_iterations=p.relax_iterations,
                           seed=p.seed)}
    return GeometrySpec(regions(p), joint_sets=[bed_set(p)], voronoi=vor)


def materials(p: UnderdipParams) -> dict:
    flaw = Material(kn=p.kn, ks=p.ks, tensile_strength=p.flaw_tensile_strength,
                    cohesion=p.flaw_cohesion, friction=p.flaw_friction,
                    breakable=not p.conventional)
    bed = Material(kn=p.kn, ks=p.ks, friction=p.bed_friction)
    return {"flaw:zone": flaw, "flaw:rock": flaw, INTERFACE: flaw, "joint:beds": bed}


def scene(p: UnderdipParams, stages=()) -> Scene:
    """The scene as data: geometry, materials, the slope boundaries, the three points, a
    quasi-static solver (local damping 0.8, mass scaling; comparisons/chapter5.py says why)
    and ``stages``."""
    # end springs: on edge elements the failed mass read after the failure depends on the
    # time step (docs/cases/underdip.md, "On edge elements"); not switched yet
    solver = {"new_contact_material": "joint:beds", "mass_scaling": True, "damping": 0.8,
              "edge_elements": False}
    return Scene(geometry(p), materials(p), density=p.density, block_E=p.block_E,
                 block_nu=p.block_nu, groups=CENTRIFUGE_GROUPS,
                 boundaries=CENTRIFUGE_BOUNDARIES, points=monitoring_points(p),
                 stages=list(stages), solver=solver, name="underdip")
