"""Highland Valley Copper, Lornex pit south-east wall: block toppling under 15 mining blocks
(thesis chapter 6, sections 6.4-6.8, Tables 6.1-6.5).

Geometry (m), x to the right, y the elevation (m above sea level), the slope facing +x (so the
faults dipping into the slope are ``dip_direction="left"``, the secondary joints dipping out
of it ``"right"``). The thesis gives the section only in figures (6.9-6.13, 6.16); the
reconstruction below follows its words, and **every number not in the text is an assumption**:

- the section is 400 m wide (x = 0..400) between elevations 1275 and 1625 m (fig. 6.16's axes);
- **assumption**: the final wall is one 35 degree face (the text's "around 35") 200 m high,
  from the crest at (60, 1625) to the final toe at (345.6, 1425); a 60 m crest plateau behind
  it and the final pit floor at 1425 in front (the benches are not modelled: the face is their
  overall slope);
- **assumption (the mining blocks, fig. 6.9 not given)**: before mining the wall stands down
  to the pit floor at 1515 m; the 15 blocks deepen the pit in 6 lifts of 15 m (1515 -> 1425)
  in front of the final face. Each lift ends with a "toe pass" (the strip within
  ``TOE_WIDTH`` = 30 m horizontally of the final face) after its "bench passes" (the rest of
  the lift out to x = 400, split in equal widths, mined from the pit side inwards). Table 6.4
  names the passes: blocks 2, 5, 8, 11, 13, 15 are toe passes, so the lifts are {1, 2},
  {3, 4, 5}, {6, 7, 8}, {9, 10, 11}, {12, 13}, {14, 15} (one, two, two, two, one and one bench
  pass). This matches the thesis's finding that the toe blocks, next to the slope, move it
  most;
- in-dipping faults: dip 70 into the slope, 30 m apart (normal), persistent; secondary joints
  at 125 degrees from horizontal (55 out of the slope), 15 m apart, persistent (the thesis:
  "the two joints intersected each other to form blocks"); **assumption**: the sets are
  shifted 0.37 and 0.29 of their spacing off the final toe (no joint through a corner of a
  region: a sliver);
- **assumption (the toppling zone, fig. 6.12 not given)**: the flaws (Voronoi blocks of
  ``edge_length``, 1.4 m in the thesis) fill the rock within ``zone_depth`` = 60 m (normal) of
  the final face, between the final toe and the crest (the band of horizontal width
  zone_depth / sin 35 behind the face, cut off by the model's left side near the crest);
  **leave out what the scene does not need**: elsewhere (behind the zone, below the pit
  floor, in the mining blocks) the joints alone cut the rock into 15 x 30 m blocks;
- **assumption (the RMR zones, figs. 6.6, 6.13 and 6.17 not given)**: Table 6.5 has four RMR
  classes; the zone is RMR 40-44 above 1575 m (the weak crest), 45-49 between 1515 and 1575 m,
  60-64 below 1515 m (fig. 6.17 shows 60-64 at the toe); the rock behind the zone and the
  mining blocks RMR 65-69 and 60-64. Each class takes Table 6.1/6.2 at its lower bound (40,
  45, 60, 65);
- boundaries: base (y = 1275) fixed, both sides on rollers (hold x);
- **assumption (the prisms, fig. 6.10 not given)**: SMP 560 is the lowest ("at the bottom of
  the slope"), then SMP 454, 468 and 413 up the pre-mining face, at elevations 1530, 1555,
  1580 and 1605 m, 1 m inside the face;
- water table (fig. 6.5, "near the slope surface"): **assumption** ``water_depth`` = 10 m
  below the final surface (crest, face and pit floor); it lies below the mining blocks;
- in-situ stress: geostatic from the pre-mining surface, sh / sv = 1.5 (Tosney 2001);
  **assumption** density 2700 kg/m3 (granodiorite; the thesis gives none).

Materials (Tables 6.1, 6.3, 6.5): flaws of each zone: Table 6.5's kn, ks (calibrated by the
thesis, not by us), Table 6.1's c and friction, T = ``tensile`` (0.1 MPa, the site estimate);
region boundaries through intact rock take the weaker side's flaw material, except the
toppling zone's back boundary (zone | rock), which is glued: **assumption** -- in the thesis
the flaws fill whole joint-bounded blocks, so the zone's back follows the joints; here it is
one straight line parallel to the face, and breakable it became a 60 m deep planar rupture
along which the whole zone slid (quick variant, first trial), an artefact of the
reconstruction. Faults kn 4, ks 1 GPa/m, c 6 kPa (the gouge's residual: kept after slip),
friction 12, T 0; secondary joints kn 4, ks 1 GPa/m, c 0, friction 25, T 0.
**Assumption**: the blocks are elastic with one modulus, 23.7 GPa (RMR 65, Table 6.2) and nu
0.3 (the DEM has one block modulus: the zones' deformability differs through the flaw
stiffness, as the thesis calibrated it). The joint-bounded rock (no flaws) takes Table 6.5's
RMR 65-69 (rock) or 60-64 (mining blocks) stiffness on its region boundaries. Conventional
mode: flaws unbreakable (intact rock glued).

Stages (``stages``): gravity; the in-situ stress; the rock at 10 x its strength (c, T of the
flaws) solved ("brought to equilibrium under high strength", thesis 6.6), the real strengths,
solved; the water table, solved; then each group of ``stage_blocks``: its blocks excavated,
solved (``Solve`` with ``failure_displacement``: a stage whose fastest block moves more than
that is stopped and reported "failed", not run for ever; and at most ``max_steps`` steps: a
stage still moving then is reported "failed" or "moving" by ``monitor.verdict``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import shapely
from shapely.geometry import Polygon, box

from dem_core.geometry import GeometrySpec, JointSet, Region, Voronoi
from dem_core.workflow.insitu import InSitu
from dem_core.contact.materials import Material
from dem_core.workflow.scene import Boundary, Scene
from dem_core.workflow.stages import ChangeMaterial, Excavate, Gravity, Solve
from dem_core.workflow.water import WaterTable

X_END, Y_BASE, Y_CREST = 400.0, 1275.0, 1625.0
FACE_DIP, CREST_X, Y_TOE, Y_PREMINING = 35.0, 60.0, 1425.0, 1515.0
LIFT_HEIGHT, TOE_WIDTH = 15.0, 30.0
LIFTS = ((1, 2), (3, 4, 5), (6, 7, 8), (9, 10, 11), (12, 13), (14, 15))   # last: toe pass
TOE_PASSES = tuple(lift[-1] for lift in LIFTS)
PRISMS = {"SMP 560": 1530.0, "SMP 454": 1555.0, "SMP 468": 1580.0, "SMP 413": 1605.0}
Y_WEAK_CREST = 1575.0
# Table 6.1 (c Pa, friction deg), Table 6.2 (E Pa), Table 6.5 (kn, ks Pa/m) by RMR class
RMR = {40: dict(cohesion=0.7e6, friction=29.0, E=5.6e9, kn=11e9, ks=3.5e9, m=0.39, s=4.54e-5),
       45: dict(cohesion=0.7e6, friction=33.0, E=7.5e9, kn=14e9, ks=4.5e9, m=0.55, s=1.04e-4),
       60: dict(cohesion=1.0e6, friction=43.0, E=17.8e9, kn=34e9, ks=11e9, m=1.61, s=1.27e-3),
       65: dict(cohesion=1.2e6, friction=46.0, E=23.7e9, kn=46e9, ks=15e9, m=2.30, s=2.93e-3)}
UCS, MI, NU = 65e6, 28.0, 0.3
HIGH_STRENGTH = 10.0            # the pre-mining equilibrium's strength factor (c and T)
FAULT = Material(kn=4e9, ks=1e9, cohesion=6e3, residual_cohesion=6e3, friction=12.0)
SECONDARY = Material(kn=4e9, ks=1e9, cohesion=0.0, friction=25.0)
ALL_BLOCKS = tuple((b,) for b in range(1, 16))


@dataclass(frozen=True)
class LornexParams:
    """The scene's parameters (SI units, angles in degrees); defaults are the thesis's run."""

    edge_length: float = 1.4
    zone_depth: float = 60.0
    relax_iterations: int = 20
    seed: int = 1
    tensile: float = 0.1e6
    conventional: bool = False
    k_ratio: float = 1.5
    density: float = 2700.0
    water_depth: float = 10.0
    fault_spacing: float = 30.0
    secondary_spacing: float = 15.0
    block_E: float = 23.7e9
    stage_blocks: tuple = ALL_BLOCKS          # the blocks excavated before each solve
    max_steps: int = 60_000                   # per solve
    failure_displacement: float = 20.0        # m: a solve stops when a block moved this far

    def __post_init__(self):
        for name in ("edge_length", "zone_depth", "density", "fault_spacing",
                     "secondary_spacing", "block_E", "failure_displacement"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be finite and > 0, got {v!r}")
        if not 0.0 < self.edge_length <= 20.0:
            raise ValueError(f"edge_length {self.edge_length!r} m must be in (0, 20]")
        if not 0.0 < self.zone_depth <= 100.0:
            raise ValueError(f"zone_depth {self.zone_depth!r} m must be in (0, 100]")
        if not (math.isfinite(self.tensile) and self.tensile >= 0):
            raise ValueError(f"tensile {self.tensile!r} Pa must be >= 0")
        if not (math.isfinite(self.k_ratio) and self.k_ratio >= 0):
            raise ValueError(f"k_ratio {self.k_ratio!r} must be >= 0")
        if not 0.0 <= self.water_depth < 100.0:
            raise ValueError(f"water_depth {self.water_depth!r} m must be in [0, 100)")
        if int(self.max_steps) != self.max_steps or self.max_steps <= 0:
            raise ValueError(f"max_steps must be an integer > 0, got {self.max_steps!r}")
        flat = [b for group in self.stage_blocks for b in group]
        if sorted(flat) != sorted(set(flat)) or not set(flat) <= set(range(1, 16)):
            raise ValueError(f"stage_blocks {self.stage_blocks!r} must name mining blocks 1-15 "
                             "at most once each")

    def with_(self, **changes) -> "LornexParams":
        return replace(self, **changes)


def x_face(y: float) -> float:
    """x (m) of the final 35 degree face at elevation y."""
    return CREST_X + (Y_CREST - y) / math.tan(math.radians(FACE_DIP))


def final_region() -> Region:
    """The section after mining (what the toppling zone is measured from)."""
    return Region("final", [(0.0, Y_BASE), (X_END, Y_BASE), (X_END, Y_TOE), (x_face(Y_TOE), Y_TOE),
                            (CREST_X, Y_CREST), (0.0, Y_CREST)])


def premining_surface() -> list:
    """The ground surface before mining, left to right (m)."""
    return [(0.0, Y_CREST), (CREST_X, Y_CREST), (x_face(Y_PREMINING), Y_PREMINING),
            (X_END, Y_PREMINING)]


def profile() -> list:
    """The section before mining (m), counter-clockwise from the bottom-left corner."""
    top = premining_surface()
    return [(0.0, Y_BASE), (X_END, Y_BASE)] + top[::-1][:-1] + [top[0]]


def face():
    """The pre-mining face as ((x_toe, y_toe), (x_crest, y_crest)), m."""
    return (x_face(Y_PREMINING), Y_PREMINING), (CREST_X, Y_CREST)


def monitoring_points() -> dict:
    """The prisms, 1 m inside the face at their elevations (module docstring)."""
    t = math.radians(FACE_DIP)
    inward = np.array([-math.sin(t), -math.cos(t)])
    return {k: tuple(map(float, np.array([x_face(y), y]) + inward)) for k, y in PRISMS.items()}


def mining_blocks() -> dict:
    """{block number: polygon} of the 15 mining blocks (module docstring)."""
    out = {}
    for i, lift in enumerate(LIFTS):
        y1 = Y_PREMINING - i * LIFT_HEIGHT
        y0 = y1 - LIFT_HEIGHT
        toe = Polygon([(x_face(y0), y0), (x_face(y0) + TOE_WIDTH, y0),
                       (x_face(y1) + TOE_WIDTH, y1), (x_face(y1), y1)])
        out[lift[-1]] = toe
        benches = lift[:-1]
        xs = np.linspace(X_END, x_face(y1) + TOE_WIDTH, len(benches) + 1)
        for b, (xa, xb) in zip(benches, zip(xs[:-1], xs[1:])):
            outer = Polygon([(xb, y0), (xa, y0), (xa, y1), (xb, y1)])
            out[b] = outer.difference(toe) if xb < x_face(y0) + TOE_WIDTH else outer
    return out


def block_name(b: int) -> str:
    return f"block{b:02d}"


def toppling_zone(p: LornexParams) -> Polygon:
    """The rock within ``zone_depth`` (normal) of the final face between the final toe and
    crest levels: the band of horizontal width zone_depth / sin(35) behind the face, cut off
    at the model's left side (60 m reach beyond it at the crest)."""
    w = p.zone_depth / math.sin(math.radians(FACE_DIP))
    band = Polygon([(x_face(Y_TOE), Y_TOE), (CREST_X, Y_CREST), (CREST_X - w, Y_CREST),
                    (x_face(Y_TOE) - w, Y_TOE)])
    return band.intersection(box(0.0, Y_BASE, X_END, Y_CREST))


def regions(p: LornexParams) -> list:
    """The zones (``zone_crest`` RMR 40, ``zone_upper`` 45, ``zone_toe`` 60), the rock behind
    (``rock``, 65) and the 15 mining blocks (``block01``..``block15``, 60)."""
    final = final_region().polygon()
    zone = toppling_zone(p)
    parts = {"zone_crest": zone.intersection(box(0, Y_WEAK_CREST, X_END, Y_CREST)),
             "zone_upper": zone.intersection(box(0, Y_PREMINING, X_END, Y_WEAK_CREST)),
             "zone_toe": zone.intersection(box(0, Y_BASE, X_END, Y_PREMINING)),
             "rock": final.difference(zone)}
    parts.update({block_name(b): g for b, g in sorted(mining_blocks().items())})
    out = []
    for name, geom in parts.items():
        pieces = sorted((g for g in getattr(geom, "geoms", [geom])
                         if g.geom_type == "Polygon" and g.area > 1e-6), key=lambda g: -g.area)
        for i, g in enumerate(pieces):
            g = shapely.orient_polygons(g.simplify(1e-9))
            out.append(Region(name if i == 0 else f"{name}_{i + 1}",
                              np.asarray(g.exterior.coords)[:-1].tolist()))
    return out


def rmr_of(region_name: str) -> int:
    """The RMR class (lower bound) of a region (module docstring)."""
    for key, rmr in (("zone_crest", 40), ("zone_upper", 45), ("zone_toe", 60), ("rock", 65)):
        if region_name.startswith(key):
            return rmr
    return 60                                      # the mining blocks


def intact(p: LornexParams, rmr: int, factor: float = 1.0) -> Material:
    """The intact rock (flaws) of an RMR class, strengths times ``factor``."""
    r = RMR[rmr]
    return Material(kn=r["kn"], ks=r["ks"], tensile_strength=factor * p.tensile,
                    cohesion=factor * r["cohesion"], friction=r["friction"],
                    breakable=not p.conventional)


def geometry(p: LornexParams) -> GeometrySpec:
    regs = regions(p)
    toe = (x_face(Y_TOE), Y_TOE)
    joints = [JointSet("faults", 70.0, p.fault_spacing, dip_direction="left", origin=toe,
                       offset=0.37 * p.fault_spacing),
              JointSet("secondary", 55.0, p.secondary_spacing, dip_direction="right",
                       origin=toe, offset=0.29 * p.secondary_spacing)]
    vor = {r.name: Voronoi(edge_length=p.edge_length, relax_iterations=p.relax_iterations,
                           seed=p.seed + i)
           for i, r in enumerate(regs) if r.name.startswith("zone")}
    return GeometrySpec(regs, joint_sets=joints, voronoi=vor)


def materials(p: LornexParams, factor: float = 1.0) -> dict:
    """Contact materials by name: flaws and region boundaries (intact rock, the weaker
    side's), the two joint sets. ``factor`` multiplies the intact rock's c and T."""
    regs = regions(p)
    out = {"joint:faults": FAULT, "joint:secondary": SECONDARY}
    for r in regs:
        out[f"flaw:{r.name}"] = intact(p, rmr_of(r.name), factor)
    polys = [r.polygon() for r in regs]
    for i, j in ((i, j) for i in range(len(regs)) for j in range(i + 1, len(regs))):
        if polys[i].buffer(1e-6).intersection(polys[j].boundary).length > 1e-3:  # touching
            a, b = regs[i].name, regs[j].name
            m = intact(p, min(rmr_of(a), rmr_of(b)), factor)
            if {a.split("_")[0], b.split("_")[0]} == {"zone", "rock"}:
                m = replace(m, breakable=False)        # the zone's back: glued (docstring)
            out[f"boundary:{a}|{b}"] = m
    return out


def water_table(p: LornexParams) -> WaterTable:
    """The phreatic surface ``water_depth`` below the final surface (module docstring)."""
    d = p.water_depth
    return WaterTable(((0.0, Y_CREST - d), (CREST_X, Y_CREST - d), (x_face(Y_TOE), Y_TOE - d),
                       (X_END, Y_TOE - d)))


def stages(p: LornexParams) -> list:
    """The stage list (module docstring)."""
    solve = Solve(1e-5, p.max_steps, failure_displacement=p.failure_displacement)
    real = materials(p)
    out = [Gravity(1.0), InSitu.geostatic(p.density, p.k_ratio, surface=premining_surface()),
           solve]
    for name, m in real.items():
        if not name.startswith("joint:"):
            out.append(ChangeMaterial(name, {"tensile_strength": m.tensile_strength,
                                             "cohesion": m.cohesion}))
    out += [solve, water_table(p), solve]
    for group in p.stage_blocks:
        out += [Excavate(block_name(b)) for b in group] + [solve]
    return out


def mining_stage_indices(p: LornexParams) -> tuple:
    """(index of the pre-mining equilibrium's solve, [index of the solve after each group of
    ``stage_blocks``]) in ``stages(p)``."""
    st = stages(p)
    first = next(i for i, s in enumerate(st) if isinstance(s, Excavate)) - 1
    after = [i for i, s in enumerate(st) if isinstance(s, Solve) and i > first]
    return first, after


def scene(p: LornexParams, with_stages: bool = True) -> Scene:
    """The scene as data (``dem_core.workflow.scene``): geometry, the high-strength materials (the
    stages lower them to the real ones), boundaries, the prisms, the solver and the stages."""
    groups = {"base": {"touching": "bottom"}, "left side": {"touching": "left"},
              "right side": {"touching": "right"},
              "side walls": {"union": ["left side", "right side"]},
              "sides": {"minus": ["side walls", "base"]}}
    solver = {"mass_scaling": True, "damping": 0.8, "new_contact_material": "joint:secondary",
              # end springs, kept: on edge elements the damaged slope fails in the first
              # mining stage (docs/cases/lornex.md, "On edge elements")
              "edge_elements": False}
    return Scene(geometry(p), materials(p, HIGH_STRENGTH), density=p.density, block_E=p.block_E,
                 block_nu=NU, groups=groups,
                 boundaries=[Boundary("base"), Boundary("sides", x=True, y=False,
                                                        rotation=False)],
                 points=monitoring_points(), stages=stages(p) if with_stages else [],
                 solver=solver, name="lornex",
                 after_failure="continue")   # the mine went on; Table 6.4 is read at the end
