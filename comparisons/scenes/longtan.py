"""Longtan intake slope, block-toppling centrifuge model of Zhang et al. (2006/2007) (thesis 4.3,
tables 4.2 and 4.3).

Geometry (m), origin at the bottom-left corner of the model, the slope facing +x (so the joints
dipping into the slope are ``dip_direction="left"``, those dipping with the face ``"right"``):

- the model is 0.752 m wide (thesis fig. 4.23, the only dimension given);
- **assumption (figs 4.21-4.23 carry no scale beyond the width; Zhang et al.'s paper was not
  available)**: a 0.40 m high slope with a 75 degree face on a 0.10 m thick base (0.50 m in
  all), crest from x = 0, the face going down to the toe at the model's right side (no toe
  bench). 75 degrees makes interlayer slip kinematically possible (face dip > 90 - 60 + 37 =
  67, Goodman & Bray), and 0.5 m of model material of 23.5 kN/m3 at 130 g carries about
  1.5 MPa at its base, the order of the bridges' strength;
- the continuous joints (column sides) dip 60 degrees into the slope, **assumption**: 50 mm
  apart (normal spacing; about six columns daylight in the face), one of them through the
  toe; they cut the whole model, base included, as in the adhikary scene;
- the cross joints (column bases) dip 60 degrees with the face, **assumption**: 100 mm apart
  (normal), twice the column spacing, so that every cross joint meets the columns at the same
  phase and the joint/bridge pattern repeats column by column: in each column a cross joint is
  intact over the back (1 - k) of its trace (the rock bridge, on the side away from the face)
  and open over the fraction k in front of it (with the bridges at the front, the face cuts
  the fronts off the traces near it and leaves blocks on open frictionless joints daylighting
  in the face, loose at 1 g). The set is shifted one column spacing off the toe (a cross
  joint through the toe cuts a sliver off it). k = 0.8 in the toe column (the column between
  the continuous joint through the toe and the next one behind it, over the model's full
  height), 0.7 elsewhere;
- **leave out what a scene does not need**: Voronoi flaws (block edge ``edge_length``) fill
  only the zone within ``zone_depth`` (normal) of the face, between the toe and crest levels,
  where the rupture forms (``zone_depth=None``: all the rock). Behind it the joints cut the
  rock into rhombic blocks and every bridge is one flaw contact of the same strength (the
  joint lines cut the rock fully there: joint over the open part, flaw over the bridge);
- the snapping of joint tips to Voronoi cells moves each tip by up to half a cell, so a bridge
  needs a few cells: ``edge_length`` <= (1 - k) x the trace across a column / 2 (5.8 mm for
  the toe column's 11.5 mm bridges);
- boundaries as in the adhikary scene: fixed base (blocks touching y = 0), rollers on both
  sides (blocks touching x = 0 or x = 0.752 hold x);
- points A (crest, 5 mm behind the crest edge, 2 mm deep) and B (mid-face, 2 mm inside).

Materials (thesis section 4.3, tables 4.2, 4.3): blocks E 2.0 GPa, nu 0.25, unit weight 23.5
kN/m3; flaws kn 600, ks 400 GPa/m, T 4.81 MPa ("tensile strength of the jointed rock"); column
sides friction 37, cohesion 0 (T 0); column bases friction 0.

- **Derived**: the conventional model's base cohesions 0.316 (toe) and 0.474 MPa (others) are
  (1 - k) x 1.58 MPa: the bridges' strength smeared over a fully persistent cross joint. So the
  intact model rock (the flaws) has c = 1.58 MPa. Its friction is not given; it is taken 0
  as the bases': the smearing c_base = (1 - k) c_bridge holds only with the same friction on
  bridge and joint (with 37 degrees on the bridges the damage model's bases would be far
  stronger than the conventional ones, under compression).
- The flaws are the intact rock everywhere (inside the columns too), so the intact rock is
  purely cohesive (c 1.58 MPa, T 4.81 MPa).
- Damage model: the cross joints are open over their persistent part (no cohesion, no tension,
  friction 0: they carry compression only) and the bridges are intact rock with flaws.
- Conventional mode (the thesis's conventional UDEC): fully persistent cross joints with the
  smeared cohesion (0.316 / 0.474 MPa, friction 0, no tension) and unbreakable flaws.
  **Assumption**: the smeared cohesion stays after slip (plastic, as in the Goodman-Bray
  analysis Zhang et al. extended to non-persistent bases); brittle, with friction 0, the
  bases unzip at the first overstress (in a trial the slope failed at the first level, 40 g).
  The region interfaces inside the rock are flaws (glued too); those along the toe column's
  sides are column joints.
- **Assumption**: the joints' stiffness is not given; taken equal to the flaws'.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import shapely
from shapely.geometry import Polygon

from dem_core.geometry import (GeometrySpec, JointSet, Region, Voronoi, slope_profile,
                               zone_polygon_along_face)
from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.workflow.scene import Scene
from dem_core.workflow.scene import build_model as build_scene_model
from dem_core.units import STANDARD_GRAVITY

from . import CENTRIFUGE_BOUNDARIES, CENTRIFUGE_GROUPS, old_param_names

WIDTH, SLOPE_HEIGHT, BASE, FACE_DIP = 0.752, 0.40, 0.10, 75.0
HEIGHT = SLOPE_HEIGHT + BASE
UNIT_WEIGHT = 23.5e3
DENSITY = UNIT_WEIGHT / STANDARD_GRAVITY
JOINT_DIP = 60.0                 # both sets, degrees
INTACT_COHESION = 1.58e6         # 0.474 / (1 - 0.7) = 0.316 / (1 - 0.8), Pa


@old_param_names
@dataclass(frozen=True)
class LongtanParams:
    """The scene's parameters (SI units, angles in degrees); defaults are the thesis's run."""

    edge_length: float = 0.005
    zone_depth: float | None = 0.20          # m normal to the face; None: flaws everywhere
    relax_iterations: int = 20
    seed: int = 1
    column_spacing: float = 0.050
    cross_spacing: float = 0.100
    persistence_toe: float = 0.8
    persistence: float = 0.7
    flaw_tensile_strength: float = 4.81e6
    flaw_cohesion: float = INTACT_COHESION
    flaw_friction: float = 0.0
    flaw_kn: float = 600e9
    flaw_ks: float = 400e9
    # fracture energies of the flaws, J/m^2 (0: brittle, the thesis's law; Material)
    flaw_fracture_energy_I: float = 0.0
    flaw_fracture_energy_II: float = 0.0
    # the regions whose flaws soften (an fnmatch pattern; "zone*": the Voronoi zone only, the
    # bridges of the joint-bounded rock behind it stay brittle: their blocks, about 0.1 m, are
    # set by the joints, not refined with edge_length, and too large for a softening length)
    flaw_softening_regions: str = "*"
    side_friction: float = 37.0
    base_friction: float = 0.0
    block_E: float = 2.0e9
    block_nu: float = 0.25
    conventional: bool = False

    def with_(self, **changes) -> "LongtanParams":
        return replace(self, **changes)


def slope_region() -> Region:
    """The whole section as one Region (what the continuum meshes)."""
    crest = WIDTH - SLOPE_HEIGHT / math.tan(math.radians(FACE_DIP))
    return slope_profile(SLOPE_HEIGHT, FACE_DIP, crest_length=crest, toe_length=0.0,
                         base_thickness=BASE, name="rock")


def profile() -> list:
    """The slope section (m), counter-clockwise from the bottom-left corner."""
    return [tuple(map(float, xy)) for xy in slope_region().exterior]


def face():
    """The free face as ((x_toe, y_toe), (x_crest, y_crest)), m."""
    crest = WIDTH - SLOPE_HEIGHT / math.tan(math.radians(FACE_DIP))
    return (WIDTH, BASE), (crest, HEIGHT)


def monitoring_points() -> dict:
    """Points A (crest) and B (mid-face), m (module docstring)."""
    (tx, ty), (cx, cy) = face()
    t = math.radians(FACE_DIP)
    inward = np.array([-math.sin(t), -math.cos(t)])
    mid = 0.5 * (np.array([tx, ty]) + np.array([cx, cy]))
    return {"A": (cx - 0.005, cy - 0.002), "B": tuple(mid + 0.002 * inward)}


def column_set(p: LongtanParams) -> JointSet:
    """The continuous joints (column sides); joint 0 runs through the toe."""
    return JointSet("columns", JOINT_DIP, p.column_spacing, dip_direction="left",
                    origin=face()[0])


def _toe_strip(p: LongtanParams) -> Polygon:
    """The toe column's strip: between the continuous joint through the toe and the next one
    behind it (a long parallelogram; clip it to the model)."""
    js = column_set(p)
    u, n = js.direction(), js.normal()
    toe = np.asarray(face()[0])
    behind = -p.column_spacing * n if n[0] > 0 else p.column_spacing * n   # towards -x
    far = 10.0 * HEIGHT * u
    return Polygon([toe - far, toe + far, toe + behind + far, toe + behind - far])


def toe_column(p: LongtanParams) -> list:
    """The toe column in the model, over its full height (a ring of (x, y), m)."""
    part = slope_region().polygon().intersection(_toe_strip(p))
    return [tuple(map(float, xy)) for xy in np.asarray(part.exterior.coords)[:-1]]


def regions(p: LongtanParams) -> list:
    """The rock split into the zone along the face (Voronoi flaws; ``zone_depth``, or all the
    rock if None) and the rest (joint-bounded blocks: the bridges are single flaw contacts),
    each split again into the toe column (names ending ``toe``) and the other columns. A part
    that falls into pieces gets numbered names (the corner of the base in front of the toe
    column)."""
    rock = slope_region().polygon()
    zone = rock if p.zone_depth is None else Polygon(zone_polygon_along_face(slope_region(),
                                                                            p.zone_depth))
    strip = _toe_strip(p)
    parts = {"zone": zone.difference(strip), "zone_toe": zone.intersection(strip),
             "rock": rock.difference(zone).difference(strip),
             "rock_toe": rock.difference(zone).intersection(strip)}
    out = []
    for name, geom in parts.items():
        pieces = sorted((g for g in getattr(geom, "geoms", [geom])
                         if g.geom_type == "Polygon" and g.area > 1e-9),
                        key=lambda g: -g.area)
        for i, g in enumerate(pieces):
            g = shapely.orient_polygons(g)
            out.append(Region(name if i == 0 else f"{name}{i + 1}",
                              np.asarray(g.exterior.coords)[:-1].tolist()))
    return out


def is_toe(region_name: str) -> bool:
    return region_name.rstrip("0123456789").endswith("toe")


def _cross_set(p, name, k, region_names) -> JointSet:
    """Cross joints dipping 60 with the face, shifted by one column spacing from the joint
    through the toe (so that no cross joint cuts a sliver off the toe). With the spacing an
    even multiple of the column spacing every trace meets the columns at the same phase: a
    bridge of (1 - k) x the trace across a column at the column's back side, then the open
    joint down-dip to its front side."""
    # the sets are 180 - 2 x 60 degrees apart: a trace crosses a column over t / sin(that)
    sin_between = math.sin(math.radians(180.0 - 2.0 * JOINT_DIP))
    period = p.column_spacing / sin_between
    if p.conventional or k >= 1.0:
        return JointSet(name, JOINT_DIP, p.cross_spacing, offset=p.column_spacing,
                        dip_direction="right", origin=face()[0], regions=region_names)
    # the offset moves where the traces meet the column joints by offset cos(between) / sin
    shift = p.column_spacing * math.cos(math.radians(180.0 - 2.0 * JOINT_DIP)) / sin_between
    return JointSet(name, JOINT_DIP, p.cross_spacing, persistence=k, trace_length=k * period,
                    offset=p.column_spacing, dip_direction="right", origin=face()[0],
                    phase=((1.0 - k) * period - shift) % period, regions=region_names)


def geometry(p: LongtanParams) -> GeometrySpec:
    ratio = p.cross_spacing / (2.0 * p.column_spacing)
    if abs(ratio - round(ratio)) > 1e-9 or round(ratio) < 1:
        raise ValueError(f"cross_spacing {p.cross_spacing} m must be an even multiple of "
                         f"column_spacing {p.column_spacing} m (same joint/bridge phase in "
                         "every column)")
    regs = regions(p)
    toe = [r.name for r in regs if is_toe(r.name)]
    others = [r.name for r in regs if not is_toe(r.name)]
    joints = [column_set(p), _cross_set(p, "cross", p.persistence, others),
              _cross_set(p, "cross_toe", p.persistence_toe, toe)]
    vor = {r.name: Voronoi(edge_length=min(p.edge_length, 0.5 * math.sqrt(Polygon(
        r.exterior).area)), relax_iterations=p.relax_iterations, seed=p.seed + i)
        for i, r in enumerate(regs) if r.name.startswith("zone")}
    return GeometrySpec(regs, joint_sets=joints, voronoi=vor)


def materials(p: LongtanParams) -> dict:
    flaw = Material(kn=p.flaw_kn, ks=p.flaw_ks, tensile_strength=p.flaw_tensile_strength,
                    cohesion=p.flaw_cohesion, friction=p.flaw_friction,
                    breakable=not p.conventional,     # conventional: intact rock is glued
                    fracture_energy_I=p.flaw_fracture_energy_I,
                    fracture_energy_II=p.flaw_fracture_energy_II)
    side = Material(kn=p.flaw_kn, ks=p.flaw_ks, tensile_strength=0.0, cohesion=0.0,
                    friction=p.side_friction)
    smeared = dict(cross=1.0 - p.persistence, cross_toe=1.0 - p.persistence_toe)
    out = {"flaw:*": flaw, "joint:columns": side, "boundary:*": flaw}
    if p.flaw_softening_regions != "*" and (p.flaw_fracture_energy_I or
                                            p.flaw_fracture_energy_II):
        brittle = replace(flaw, fracture_energy_I=0.0, fracture_energy_II=0.0)
        out.update({"flaw:*": brittle, "boundary:*": brittle,
                    f"flaw:{p.flaw_softening_regions}": flaw})
    for name in regions_material_names(p):     # the toe column's sides are continuous joints
        a, b = name.split(":", 1)[1].split("|")
        if is_toe(a) != is_toe(b):
            out[name] = side
    for name, bridge in smeared.items():
        c = bridge * p.flaw_cohesion if p.conventional else 0.0
        out[f"joint:{name}"] = Material(kn=p.flaw_kn, ks=p.flaw_ks, tensile_strength=0.0,
                                        cohesion=c, friction=p.base_friction,
                                        residual_cohesion=c)     # plastic (module docstring)
    return out


def regions_material_names(p: LongtanParams) -> list:
    """The "boundary:A|B" names that can occur between the scene's regions."""
    names = sorted(r.name for r in regions(p))
    return [f"boundary:{a}|{b}" for i, a in enumerate(names) for b in names[i + 1:]]


def scene(p: LongtanParams, stages=()) -> Scene:
    """The scene as data (``dem_core.workflow.scene``): geometry, materials, the centrifuge boundaries,
    points A and B, the quasi-static g-ramp solver (kinetic damping, mass scaling) and
    ``stages`` (e.g. one ``stages.RaiseGravity``)."""
    # (conventional mode: the materials themselves are glued, ``materials``)
    # the library's contact model: edge elements on the rigid blocks (2026-12-01; end springs
    # before: solver {"edge_elements": false}, docs/comparisons.md)
    solver = {"new_contact_material": "joint:columns", "mass_scaling": True, "damping": 0.0,
              "kinetic_damping": 100}
    return Scene(geometry(p), materials(p), density=DENSITY, block_E=p.block_E,
                 block_nu=p.block_nu, groups=CENTRIFUGE_GROUPS,
                 boundaries=CENTRIFUGE_BOUNDARIES, points=monitoring_points(), stages=list(stages),
                 solver=solver, name="longtan")


def build_model(p: LongtanParams, blocks=None, **model_options) -> Model:
    """The DEM model of the scene with its boundary conditions and points A and B
    (``dem_core.workflow.scene.build_model``; ``model_options`` override the scene's solver)."""
    return build_scene_model(scene(p), blocks, **model_options)
