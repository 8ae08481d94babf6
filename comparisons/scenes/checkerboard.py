"""Checkerboard Creek slope above the Revelstoke dam: weathering as strength loss (thesis
chapter 7, sections 7.6-7.8, Tables 7.1-7.5).

Geometry (m), x to the right, y the elevation above the model's base, the slope facing +x (the
reservoir on the right), so joints dipping into the slope are ``dip_direction="left"``. The
thesis gives the section only in figures (7.3, 7.8, 7.9: a 4000 m x 3100 m model, the area of
interest at the highway cut); **every number below that is not in its text is an assumption**,
all of them here:

- the full section is 4000 m wide and 3100 m high (fig. 7.8's dimensions); its base is y = 0;
- **assumption**: the toe of the highway cut is at (3700, 800); in front of it the ground (the
  highway and the reservoir shore) is flat at 800 m to the model's right side; the reservoir's
  water on that floor is not modelled (it presses on no part of the failing cut);
- the highway cut faces 55 degrees (text: "the ground surface slope at the highway cut around
  55"); **assumption**: it is ``cut_height`` = 70 m high; above its crest the natural slope
  rises at ``natural_slope`` = 35 degrees to the model's top (3100 m), then a plateau to x = 0.
  The height is not given; **chosen**, among 50, 60, 70 and 80 m tried with the quick model
  (docs/cases/checkerboard.md), as the lowest at which the thesis's stated outcome occurs (the
  cut fails as T is lowered below c): at 50 and 60 m the cut stood down to T = 0, at 80 m it
  failed at T = 1.5 MPa, the second level (c 2.0-2.7 MPa). This is a calibration of an
  unknown geometry to the thesis's qualitative result, not to a number of Table 7.4;
- the weathered zone is ``weathered_depth`` = 60 m deep normal to the ground surface (text);
  **assumption**: it runs along the surface from the toe of the cut up to 300 m above it
  (y = 1100: the moving area with tension cracks up to 150 m above the cut and 2-3 million m3
  moving); up the slope the rock is unweathered (text, fig. 7.12);
- **assumption (fig. 7.3 not given)**: the Columbia River fault dips 25 degrees into the slope
  and meets the ground at y = 1000 (200 m above the cut's toe); the gneiss/schist lies below it
  (so the highway cut is in gneiss: Table 7.4 starts at the weathered gneiss's UCS, 76 MPa),
  the granodiorite above ("foliated granodiorite overlying the easterly dipping Columbia River
  Fault"). The fault is the region boundary between the units (Table 7.3's "major faults");
- joints (Table 7.3), **assumption (spacings and dips not given beyond "dip in and out of the
  slope at 60-90")**: near-vertical joints dipping 85 into the slope every ``vertical_spacing``
  = 10 m (they form the toppling columns the thesis saw), cross-cutting shears dipping 65 out
  of the slope every ``shear_spacing`` = 40 m, and the shears in the gneiss dipping 70 into
  the slope every 40 m (gneiss only), all in the weathered zone; **leave out what the scene
  does not need**: the fresh rock's joints (c 5 kPa, friction 35, far from the moving zone) are
  left out, their compliance being in the fresh rock's flaws;
- flaws: Voronoi blocks of ``edge_length`` = 1.3 m (text) in the zone around the cut (the
  weathered rock within ``zone_length`` = 150 m horizontally behind the cut's crest, its whole
  60 m depth) and growing linearly to ``far_size`` over ``transition`` m outside it
  (``dem_core.geometry.ZoneSizeField``): a 4 km section of 1.3 m blocks would be 3 million;
- ``window``: the quick variant cuts the section to the box (x0, y0) .. (4000, top): the same
  ground surface, the sides on rollers and the base fixed there as on the full section
  (**assumption**: the window's sides are far enough from the cut that the rollers do not hold
  it; the quick variant's window is stated in the case);
- boundaries: base fixed, both sides on rollers (hold x);
- the water table lies ``water_depth`` = 65 m below the ground surface (text: saturated 50-80
  m below the ground), pressure on the joints (``dem_core.workflow.water``);
- points: "crest" (1 m behind and 1 m below the cut's crest), "face" (mid cut face, 1 m
  inside), "slope" (on the natural slope 100 m horizontally behind the crest, 1 m deep);
- groups besides the boundaries': "weathered_skin" (the weathered rock within 30 m of the
  ground, up the slope of the cut zone: the displacement boundary), "cut_face" (the blocks
  within two edges of the cut's face: the shotcrete), "slivers" (``sliver_groups``: blocks
  under ``SLIVER`` x edge^2 that a joint trace cuts off at a corner, excavated first).

Materials (thesis Tables 7.1-7.3; flaw stiffness after eq 3.7, section 3.4):

- flaws of each unit: c and friction from Hoek-Brown (Hoek et al. 2002 equivalent Mohr-Coulomb
  over sigma3 up to ``SIGMA3_MAX`` = 12 MPa: **assumption**, the range at which the formula
  gives Table 7.2's granodiorite row, 3.3 MPa and 41 degrees; Table 7.2's cohesions and
  frictions are used as printed for the units not varied), T = c (the thesis's starting point
  of the back-analysis); the weathered units take ``ucs`` as their sigma_ci (Table 7.4 varies
  it, 76 -> 30 MPa) with Table 7.2's GSI and mi; ``tensile`` overrides the weathered gneiss's T;
- flaw stiffness by eq. 3.7: kn = (K + 4G/3) / dz_min of the unit's Table 7.1 E and nu, with
  dz_min = ``edge_length`` (the smallest block next to a contact), ks = kn / 10 (Table 7.2's
  ratio); region boundaries inside one unit (weathered/fresh) are flaws of the weaker side;
- the blocks are elastic with one modulus (the DEM has one): the weathered rock's 3.6 GPa, nu
  0.27 (Table 7.1), where the failure is; the fresh rock's stiffness is in its flaws; density
  2700 kg/m3 (**assumption**, none given);
- joints and the fault: Table 7.3 (kn, ks, friction, c; T 0);
- conventional mode (the thesis's conventional UDEC): flaws unbreakable.

Stages (``base_stages``; ``scene`` puts the slivers' excavation first): gravity solved at
``HIGH_STRENGTH`` x the flaws' c and T, the real strengths (``change_material``), solved, the
water table, solved; the case appends its own (a ``strength_schedule`` of the weathered gneiss's
flaw T, a ``displace`` of the weathered skin, or cables and a schedule).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon, box

from continuum_ref import hoek_brown as hb
from dem_core.contact.elastic import kn_from_zone
from dem_core.geometry import GeometrySpec, JointSet, Region, Voronoi, ZoneSizeField
from dem_core.contact.materials import Material
from dem_core.workflow.scene import Boundary, Scene
from dem_core.workflow.stages import ChangeMaterial, Excavate, Gravity, Solve
from dem_core.workflow.water import WaterTable

WIDTH, HEIGHT = 4000.0, 3100.0
TOE = (3700.0, 800.0)
CUT_DIP = 55.0
FAULT_DIP, FAULT_OUTCROP_Y = 25.0, 1000.0
WEATHERED_TOP_Y = 1100.0
SIGMA3_MAX = 12e6                       # Pa, module docstring
SLIVER = 0.01                           # blocks under this x edge^2 are excavated first
HIGH_STRENGTH = 10.0                    # the flaws' c and T while gravity is applied
DENSITY = 2700.0
# Table 7.1 (E Pa, nu) and Table 7.2 (sci Pa, GSI, mi, friction deg, c Pa, st Pa) per unit
UNITS = {
    "gneiss": dict(E=6.5e9, nu=0.25, sci=133e6, gsi=60, mi=26, friction=48.0, c=5.0e6),
    "weathered_gneiss": dict(E=3.6e9, nu=0.27, sci=76e6, gsi=35, mi=20, friction=34.0, c=2.4e6),
    "granodiorite": dict(E=17.7e9, nu=0.23, sci=100e6, gsi=35, mi=29, friction=41.0, c=3.2e6),
    "weathered_granodiorite": dict(E=3.6e9, nu=0.27, sci=75e6, gsi=35, mi=26, friction=36.0,
                                   c=2.5e6),
}
FAULT_E, FAULT_NU = 0.5e9, 0.3
# Table 7.3: kn, ks (Pa/m), friction (deg), c (Pa)
JOINTS = {"cross_shears": (5e9, 1e9, 25.0, 0.0), "vertical_fresh": (50e9, 5e9, 35.0, 5e3),
          "vertical": (2e9, 0.4e9, 25.0, 0.0), "fault": (0.5e9, 0.1e9, 18.0, 0.0),
          "gneiss_shears": (2e9, 0.4e9, 18.0, 0.0)}
WEATHERED = ("weathered_gneiss", "weathered_granodiorite")


@dataclass(frozen=True)
class CheckerboardParams:
    """The scene's parameters (SI units, angles in degrees); defaults are the thesis's run."""

    edge_length: float = 1.3
    zone_length: float = 150.0
    far_size: float = 150.0
    transition: float = 300.0
    relax_iterations: int = 10
    seed: int = 1
    window: tuple | None = None            # (x0, y0): the section cut to x >= x0, y >= y0
    cut_height: float = 70.0
    natural_slope: float = 35.0
    weathered_depth: float = 60.0
    vertical_spacing: float = 10.0
    shear_spacing: float = 40.0
    water_depth: float | None = 65.0       # None: dry
    ucs: float = 76e6                      # sigma_ci of the weathered units, Pa
    tensile: float | None = None           # T of the weathered gneiss's flaws; None: = c
    conventional: bool = False
    block_E: float = 3.6e9
    block_nu: float = 0.27

    def __post_init__(self):
        for name in ("edge_length", "zone_length", "far_size", "transition", "cut_height",
                     "weathered_depth", "vertical_spacing", "shear_spacing", "ucs", "block_E"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"CheckerboardParams.{name} must be finite and > 0, got {v!r}")
        if not 10.0 <= self.natural_slope < CUT_DIP:
            raise ValueError(f"natural_slope {self.natural_slope} must be in [10, {CUT_DIP})")
        if self.far_size < self.edge_length:
            raise ValueError(f"far_size {self.far_size} must be >= edge_length "
                             f"{self.edge_length}")
        if self.tensile is not None and not (math.isfinite(self.tensile) and self.tensile >= 0):
            raise ValueError(f"tensile {self.tensile!r} must be >= 0 Pa")
        if self.water_depth is not None and not self.water_depth > 0:
            raise ValueError(f"water_depth {self.water_depth!r} must be > 0 m (or None)")
        if self.window is not None:
            x0, y0 = self.window
            if not (0 <= x0 < crest(self)[0] - self.zone_length and 0 <= y0 < TOE[1]
                    - self.weathered_depth):
                raise ValueError(f"window {self.window!r} must leave the cut zone inside: "
                                 f"x0 < {crest(self)[0] - self.zone_length:.0f}, "
                                 f"y0 < {TOE[1] - self.weathered_depth:.0f} m")

    def with_(self, **changes) -> "CheckerboardParams":
        return replace(self, **changes)


def crest(p: CheckerboardParams) -> tuple:
    """The highway cut's crest (x, y), m."""
    return (TOE[0] - p.cut_height / math.tan(math.radians(CUT_DIP)), TOE[1] + p.cut_height)


def surface(p: CheckerboardParams) -> list:
    """The ground surface from the model's left side to its right side, [(x, y)] m."""
    cx, cy = crest(p)
    top_x = cx - (HEIGHT - cy) / math.tan(math.radians(p.natural_slope))
    if top_x <= 0:
        raise ValueError(f"natural_slope {p.natural_slope} does not reach the top in the section")
    return [(0.0, HEIGHT), (top_x, HEIGHT), (cx, cy), TOE, (WIDTH, TOE[1])]


def _x0y0(p):
    return (0.0, 0.0) if p.window is None else tuple(map(float, p.window))


def section(p: CheckerboardParams) -> Polygon:
    """The modelled section (the window of it), a shapely Polygon."""
    full = Polygon([(0.0, 0.0), (WIDTH, 0.0)] + surface(p)[::-1])
    x0, y0 = _x0y0(p)
    return full.intersection(box(x0, y0, WIDTH, HEIGHT))


def _along_surface_to(p, y_top) -> LineString:
    """The ground surface from the cut's toe up the slope to elevation ``y_top``."""
    cx, cy = crest(p)
    x_top = cx - (y_top - cy) / math.tan(math.radians(p.natural_slope))
    return LineString([(x_top, y_top), (cx, cy), TOE])


def weathered_zone(p) -> Polygon:
    band = _along_surface_to(p, WEATHERED_TOP_Y).buffer(p.weathered_depth, cap_style="flat",
                                                        join_style="mitre")
    return band.intersection(section(p))


def cut_zone(p) -> Polygon:
    """The flaw zone: the weathered rock within ``zone_length`` behind the cut's crest."""
    return weathered_zone(p).intersection(box(crest(p)[0] - p.zone_length, 0.0, WIDTH, HEIGHT))


def below_fault(p) -> Polygon:
    """The part of the plane below the Columbia River fault (the gneiss side)."""
    cx, cy = crest(p)
    xf = cx - (FAULT_OUTCROP_Y - cy) / math.tan(math.radians(p.natural_slope))
    t = math.tan(math.radians(FAULT_DIP))
    far = 10 * WIDTH
    return Polygon([(xf - far, FAULT_OUTCROP_Y - far * t), (xf + far, FAULT_OUTCROP_Y + far * t),
                    (xf + far, -far), (xf - far, -far)])


def unit_of(name: str) -> str:
    return name.rstrip("0123456789")


def regions(p: CheckerboardParams) -> list:
    """The four units (fresh and weathered gneiss and granodiorite) as Regions; a unit in
    several pieces gets numbered names. A window can leave a sliver of a unit at its edge: pieces
    under 100 edge^2 are left out (a notch in the window's corner, away from the cut)."""
    sec, w, gn = section(p), weathered_zone(p), below_fault(p)
    parts = {"weathered_gneiss": w.intersection(gn), "weathered_granodiorite": w.difference(gn),
             "gneiss": sec.difference(w).intersection(gn),
             "granodiorite": sec.difference(w).difference(gn)}
    out = []
    for name, geom in parts.items():
        pieces = sorted((g for g in getattr(geom, "geoms", [geom])
                         if g.geom_type == "Polygon" and g.area > 100 * p.edge_length ** 2),
                        key=lambda g: -g.area)
        for i, g in enumerate(pieces):
            g = shapely.orient_polygons(shapely.simplify(g, 1e-6))
            out.append(Region(name if i == 0 else f"{name}{i + 1}",
                              np.asarray(g.exterior.coords)[:-1].tolist()))
    return out


def joint_sets(p: CheckerboardParams, names) -> list:
    weathered = [n for n in names if unit_of(n) in WEATHERED]
    gneiss = [n for n in names if unit_of(n) == "weathered_gneiss"]
    return [JointSet("vertical", 85.0, p.vertical_spacing, dip_direction="left", origin=TOE,
                     regions=weathered),
            JointSet("cross_shears", 65.0, p.shear_spacing, dip_direction="right", origin=TOE,
                     offset=0.5 * p.vertical_spacing, regions=weathered),
            JointSet("gneiss_shears", 70.0, p.shear_spacing, dip_direction="left", origin=TOE,
                     offset=0.25 * p.shear_spacing, regions=gneiss)]


def geometry(p: CheckerboardParams) -> GeometrySpec:
    regs = regions(p)
    zone = [list(map(float, q)) for q in np.asarray(cut_zone(p).exterior.coords)[:-1]]
    field = ZoneSizeField(zone=zone, inside=p.edge_length, outside=p.far_size,
                          transition=p.transition)
    vor = {r.name: Voronoi(edge_length=p.edge_length, relax_iterations=p.relax_iterations,
                           seed=p.seed + i, size_field=field) for i, r in enumerate(regs)}
    return GeometrySpec(regs, joint_sets=joint_sets(p, [r.name for r in regs]), voronoi=vor)


def flaw_strength(unit: str, ucs: float) -> tuple:
    """(c Pa, friction deg, Hoek-Brown tensile strength Pa) of a unit's flaws: the weathered
    units from Hoek-Brown at sigma_ci = ``ucs`` (module docstring), the fresh ones Table 7.2."""
    u = UNITS[unit]
    sci = ucs if unit in WEATHERED else u["sci"]
    mb, s, a = hb.parameters(u["gsi"], u["mi"])
    st = -hb.tensile_strength(sci, mb, s)
    if unit not in WEATHERED:
        return u["c"], u["friction"], st
    c, phi = hb.equivalent_mohr_coulomb(sci, mb, s, a, SIGMA3_MAX)
    return c, phi, st


def flaw_material(p: CheckerboardParams, unit: str) -> Material:
    u = UNITS[unit]
    c, phi, _ = flaw_strength(unit, p.ucs)
    t = p.tensile if (unit == "weathered_gneiss" and p.tensile is not None) else c
    kn = kn_from_zone(u["E"], u["nu"], p.edge_length)
    return Material(kn=kn, ks=kn / 10.0, tensile_strength=t, cohesion=c, friction=phi,
                    breakable=not p.conventional)


def _joint(name) -> Material:
    kn, ks, phi, c = JOINTS[name]
    return Material(kn=kn, ks=ks, tensile_strength=0.0, cohesion=c, friction=phi)


def materials(p: CheckerboardParams, strength_factor: float = 1.0) -> dict:
    """Contact materials by exact name (flaws per region, joints, region boundaries); the
    flaws' c and T times ``strength_factor`` (the scene starts at ``HIGH_STRENGTH``)."""
    regs = sorted(r.name for r in regions(p))
    out = {f"joint:{n}": _joint(n) for n in ("vertical", "cross_shears", "gneiss_shears")}
    for r in regs:
        out[f"flaw:{r}"] = flaw_material(p, unit_of(r))
    weaker = {"gneiss": "weathered_gneiss", "granodiorite": "weathered_granodiorite"}
    for i, a in enumerate(regs):
        for b in regs[i + 1:]:
            ua, ub = unit_of(a), unit_of(b)
            if ("gneiss" in ua) != ("gneiss" in ub):
                m = _joint("fault")                              # across the fault
            else:
                m = flaw_material(p, ua if ua in WEATHERED else ub if ub in WEATHERED
                                  else weaker[ua])
            out[f"boundary:{a}|{b}"] = out[f"boundary:{b}|{a}"] = m   # either order
    return {k: v if not v.breakable or k.startswith("joint:") or k in _fault_names(out) else
            replace(v, cohesion=v.cohesion * strength_factor,
                    tensile_strength=v.tensile_strength * strength_factor)
            for k, v in out.items()}


def _fault_names(mats) -> set:
    fault = _joint("fault")
    return {k for k, v in mats.items() if v == fault}


def strength_stages(p: CheckerboardParams) -> list:
    """``ChangeMaterial`` stages from the high starting strength to the real one (every flaw
    material whose c or T differs)."""
    real, high = materials(p), materials(p, HIGH_STRENGTH)
    return [ChangeMaterial(k, {"tensile_strength": v.tensile_strength, "cohesion": v.cohesion})
            for k, v in real.items() if v != high[k]]


def water_table(p: CheckerboardParams):
    """The phreatic surface ``water_depth`` below the ground (None when dry)."""
    if p.water_depth is None:
        return None
    return WaterTable(tuple((x, y - p.water_depth) for x, y in surface(p)))


def monitoring_points(p: CheckerboardParams | None = None) -> dict:
    p = p or CheckerboardParams()
    (cx, cy), (tx, ty) = crest(p), TOE
    t = math.radians(CUT_DIP)
    mid = np.array([(cx + tx) / 2, (cy + ty) / 2]) - 1.0 * np.array([math.sin(t), math.cos(t)])
    sx = cx - 100.0
    sy = cy + 100.0 * math.tan(math.radians(p.natural_slope)) - 1.0
    return {"crest": (cx - 1.0, cy - 1.0), "face": tuple(map(float, mid)), "slope": (sx, sy)}


def profile(p: CheckerboardParams | None = None) -> list:
    """The section's outline (m), counter-clockwise (for the figures)."""
    p = p or CheckerboardParams()
    return [tuple(map(float, q)) for q in np.asarray(section(p).exterior.coords)[:-1]]


def base_stages(p: CheckerboardParams, max_steps: int = 100_000) -> list:
    """Gravity to equilibrium at ``HIGH_STRENGTH`` x the flaws' c and T (the slope was formed
    long before it weathered: its initial stress is not a fracturing event), the real
    strengths, then the water table, each solved to equilibrium."""
    out = [Gravity(1.0), Solve(1e-5, max_steps)] + strength_stages(p) + [Solve(1e-5, max_steps)]
    wt = water_table(p)
    if wt is not None:
        out += [wt, Solve(1e-5, max_steps)]
    return out


def groups(p: CheckerboardParams) -> dict:
    """Boundary groups, the weathered surface skin (the displacement boundary) and the cut's
    face (the shotcrete)."""
    skin = _along_surface_to(p, WEATHERED_TOP_Y).buffer(0.5 * p.weathered_depth,
                                                         cap_style="flat", single_sided=False)
    skin = skin.intersection(weathered_zone(p)).difference(
        box(crest(p)[0] - p.zone_length, 0, WIDTH, HEIGHT))
    (cx, cy), (tx, ty) = crest(p), TOE
    face = LineString([(cx, cy), (tx, ty)]).buffer(2.0 * p.edge_length)
    ring = lambda g: [list(map(float, q)) for q in np.asarray(g.exterior.coords)[:-1]]  # noqa
    return {"base": {"touching": "bottom"}, "left side": {"touching": "left"},
            "right side": {"touching": "right"},
            "side walls": {"union": ["left side", "right side"]},
            "sides": {"minus": ["side walls", "base"]},
            "weathered_skin": {"inside": ring(skin)},
            "cut_face": {"inside": ring(face)}}


def sliver_groups(spec: GeometrySpec, p: CheckerboardParams) -> dict:
    """{"sliver<i>": {"inside": its polygon}} for each block under ``SLIVER`` x edge^2 (a joint
    trace passing a corner of the surface or of a cell cuts off a few-cm^2 piece, which then
    flies off on its one contact and breaks the explicit scheme); the scene excavates them
    first. The blocks are convex, so a block's own outline holds its centroid and no other."""
    from dem_core.geometry import build_block_system

    bs = build_block_system(spec)
    out = {}
    for b in np.flatnonzero(bs.area < SLIVER * p.edge_length ** 2):
        ring = bs.vertices[bs.vertex_offsets[b]:bs.vertex_offsets[b + 1]]
        out[f"sliver{len(out)}"] = {"inside": ring.tolist()}
    return out


def scene(p: CheckerboardParams, stages=None) -> Scene:
    """The scene as data; ``stages`` default ``base_stages(p)``, after the excavation of the
    slivers (``sliver_groups``)."""
    stages = base_stages(p) if stages is None else list(stages)
    spec = geometry(p)
    slivers = sliver_groups(spec, p)
    gr = groups(p)
    if slivers:
        gr.update(slivers)
        gr["slivers"] = {"union": sorted(slivers)}
        stages = [Excavate("slivers")] + stages
    return Scene(spec, materials(p, HIGH_STRENGTH), density=DENSITY, block_E=p.block_E,
                 block_nu=p.block_nu, groups=gr,
                 boundaries=[Boundary("base"), Boundary("sides", x=True, y=False,
                                                        rotation=False)],
                 points=monitoring_points(p), stages=stages,
                 solver={"new_contact_material": "joint:vertical", "mass_scaling": True,
                         "damping": 0.0, "kinetic_damping": 100,
                         # end springs, kept: on edge elements the quick section fails at
                         # the weathered strengths themselves (docs/cases/checkerboard.md)
                         "edge_elements": False},
                 name="checkerboard")
