"""Buckling of a footwall layer in an open-pit coal mine after Stead & Eberhardt (1997) (thesis
5.3.2, table 5.4, fig 5.11).

Geometry (m), origin at the bottom-left corner, the slope facing +x; the thesis gives the
height, the slope angle and the layer's thickness; every other dimension is an assumption
stated here:

- a 75 m footwall slope at 30 degrees (thesis); **assumption**: ``crest_length`` 15 m of crest
  behind it, ``toe_length`` 30 m of pit floor in front, ``floor_depth`` 15 m of rock under the
  pit floor (the model is 175 m wide and 90 m high);
- a 3.5 m layer parallel to the face (thesis), from the crest down the face and, **assumption**,
  on below the pit floor to the model's base: a footwall layer is a bed of the sequence, not
  cut at the floor, and the rock of the pit floor in front of it (the strata that were above
  it, left below the floor) is what buttresses its toe. (A layer ending at the floor level
  would have nothing in front of its toe and slide out on its 20 degree base, which is flatter
  than the 30 degree face.) Fig 5.11a shows the model without dimensions;
- three regions: the ``layer`` (the Voronoi flaws, edge ``edge_length``: the thesis's UDEC-DM
  layer is a Voronoi tessellation whose tensile strength is lowered "everywhere in the layer"),
  the ``footwall`` under the basal plane and the ``floor`` rock in front of the layer below the
  pit floor, each one block without flaws (they are not part of the mechanism) and fixed, as
  every block touching the model's base (``CENTRIFUGE_BOUNDARIES``: base fixed, rollers on the
  sides);
- the basal plane (``boundary:layer|footwall``): friction 20 degrees, no cohesion, no tension
  (thesis); **assumption**: the layer's top contact with the floor rock below the pit floor
  (``boundary:layer|floor``) is the same kind of bedding plane;
- points ``toe``, ``lower``, ``middle``, ``upper`` on the face at 5 m, H/4, H/2 and 3H/4 above the
  toe, 1 m inside the layer, and ``crest`` 1 m behind the crest edge, 1 m deep.

Materials (table 5.4): the intact layer (flaws) cohesion 0.3 MPa, friction 25, tensile strength
30 kPa; kn = ks = 1 GPa/m for the flaws and the basal plane. **Assumptions** (not in the
thesis): density 2500 kg/m3 (footwall sandstone or siltstone), blocks E 10 GPa, nu 0.25.
Conventional mode (the thesis's conventional UDEC): the same blocks with unbreakable flaws.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np
from shapely.geometry import Polygon

from dem_core.geometry import GeometrySpec, Region, Voronoi, slope_profile
from dem_core.contact.materials import Material
from dem_core.workflow.scene import Scene

from . import CENTRIFUGE_BOUNDARIES, CENTRIFUGE_GROUPS, old_param_names

HEIGHT, FACE_DIP = 75.0, 30.0                 # m, degrees (thesis)
BASAL, FLOOR = "boundary:layer|footwall", "boundary:layer|floor"


@old_param_names
@dataclass(frozen=True)
class CoalBucklingParams:
    """The scene's parameters (SI units, angles in degrees); defaults are the thesis's run
    (table 5.4) with the geometry assumptions of the module docstring."""

    layer_thickness: float = 3.5
    edge_length: float = 1.0
    relax_iterations: int = 20
    seed: int = 1
    crest_length: float = 15.0
    toe_length: float = 30.0
    floor_depth: float = 15.0
    basal_friction: float = 20.0
    flaw_tensile_strength: float = 30e3
    flaw_cohesion: float = 0.3e6
    flaw_friction: float = 25.0
    kn: float = 1e9
    ks: float = 1e9
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
                raise ValueError(f"CoalBucklingParams.{f.name} must be finite and >= 0, "
                                 f"got {v}")
        for name in ("layer_thickness", "edge_length", "crest_length", "toe_length",
                     "floor_depth", "kn", "ks", "density", "block_E"):
            if getattr(self, name) <= 0:
                raise ValueError(f"CoalBucklingParams.{name} must be > 0, got "
                                 f"{getattr(self, name)}")
        for name in ("basal_friction", "flaw_friction"):
            if not getattr(self, name) < 90.0:
                raise ValueError(f"CoalBucklingParams.{name} must be < 90 degrees, got "
                                 f"{getattr(self, name)}")
        if self.layer_thickness >= self.crest_length * math.sin(math.radians(FACE_DIP)):
            raise ValueError(f"CoalBucklingParams.layer_thickness {self.layer_thickness} m: "
                             f"the layer would reach the model's back (crest_length "
                             f"{self.crest_length} m)")

    def with_(self, **changes) -> "CoalBucklingParams":
        return replace(self, **changes)


def slope_region(p: CoalBucklingParams) -> Region:
    """The whole section as one Region."""
    return slope_profile(HEIGHT, FACE_DIP, crest_length=p.crest_length,
                         toe_length=p.toe_length, base_thickness=p.floor_depth, name="rock")


def profile(p: CoalBucklingParams | None = None) -> list:
    """The slope section (m), counter-clockwise from the bottom-left corner."""
    return [tuple(map(float, xy)) for xy in slope_region(p or CoalBucklingParams()).exterior]


def face(p: CoalBucklingParams | None = None):
    """The free face as ((x_toe, y_toe), (x_crest, y_crest)), m."""
    p = p or CoalBucklingParams()
    run = HEIGHT / math.tan(math.radians(FACE_DIP))
    return ((p.crest_length + run, p.floor_depth), (p.crest_length, p.floor_depth + HEIGHT))


def outward_normal() -> np.ndarray:
    """Unit normal of the face pointing out of the rock."""
    t = math.radians(FACE_DIP)
    return np.array([math.sin(t), math.cos(t)])


def depth_below_face(p: CoalBucklingParams, x, y) -> np.ndarray:
    """Normal distance (m) below the face's line (extended below the floor), + into the rock."""
    (tx, ty), _ = face(p)
    n = outward_normal()
    return -((np.asarray(x) - tx) * n[0] + (np.asarray(y) - ty) * n[1])


def monitoring_points(p: CoalBucklingParams | None = None) -> dict:
    """Points on the face and at the crest, m (module docstring)."""
    p = p or CoalBucklingParams()
    (tx, ty), (cx, cy) = face(p)
    t = math.radians(FACE_DIP)
    inward = -outward_normal()

    def on_face(h):
        return np.array([tx - h / math.tan(t), ty + h]) + inward
    out = {name: tuple(map(float, on_face(h))) for name, h in
           (("toe", 5.0), ("lower", HEIGHT / 4), ("middle", HEIGHT / 2),
            ("upper", 0.75 * HEIGHT))}
    out["crest"] = (cx - 1.0, cy - 1.0)
    return out


def regions(p: CoalBucklingParams) -> list:
    """The layer, the footwall under it and the floor rock in front of it (module docstring):
    the slope cut by the face's line (extended) and the basal plane."""
    rock = slope_region(p).polygon()
    (tx, ty), _ = face(p)
    n, t = outward_normal(), math.radians(FACE_DIP)
    d = np.array([math.cos(t), -math.sin(t)])           # down the face
    big = 10.0 * (HEIGHT + p.crest_length + p.toe_length + p.floor_depth)
    toe = np.array([tx, ty])

    def band(d0, d1):          # the strip between depths d0 and d1 below the face's line
        a, b = toe - d0 * n, toe - d1 * n
        return Polygon([a - big * d, a + big * d, b + big * d, b - big * d])
    parts = {"layer": band(0.0, p.layer_thickness),
             "footwall": band(p.layer_thickness, big), "floor": band(-big, 0.0)}
    out = []
    for name, strip in parts.items():
        g = rock.intersection(strip)
        if g.geom_type != "Polygon" or g.area <= 0:
            raise ValueError(f"the {name} region is not one polygon (check the dimensions)")
        ring = np.asarray(g.exterior.coords)[:-1]
        # the face's line meets the strips' sides at the toe: drop the repeated point
        step = np.hypot(*(ring - np.roll(ring, 1, axis=0)).T)
        out.append(Region(name, ring[step > 1e-6].tolist()))
    return out


def geometry(p: CoalBucklingParams) -> GeometrySpec:
    vor = {"layer": Voronoi(edge_length=p.edge_length, relax_iterations=p.relax_iterations,
                            seed=p.seed)}
    return GeometrySpec(regions(p), voronoi=vor)


def materials(p: CoalBucklingParams) -> dict:
    flaw = Material(kn=p.kn, ks=p.ks, tensile_strength=p.flaw_tensile_strength,
                    cohesion=p.flaw_cohesion, friction=p.flaw_friction,
                    breakable=not p.conventional)
    bed = Material(kn=p.kn, ks=p.ks, friction=p.basal_friction)
    return {"flaw:layer": flaw, "flaw:footwall": flaw, "flaw:floor": flaw,
            BASAL: bed, FLOOR: bed}


def scene(p: CoalBucklingParams, stages=()) -> Scene:
    """The scene as data: geometry, materials, the slope boundaries, the points, a
    quasi-static solver (local damping 0.8, mass scaling; comparisons/chapter5.py says why)
    and ``stages``."""
    # the library's contact model: edge elements on the rigid blocks (2026-12-01; end
    # springs before: solver {"edge_elements": false}, docs/comparisons.md)
    solver = {"new_contact_material": BASAL, "mass_scaling": True, "damping": 0.8}
    return Scene(geometry(p), materials(p), density=p.density, block_E=p.block_E,
                 block_nu=p.block_nu, groups=CENTRIFUGE_GROUPS,
                 boundaries=CENTRIFUGE_BOUNDARIES, points=monitoring_points(p),
                 stages=list(stages), solver=solver, name="coal_buckling")
