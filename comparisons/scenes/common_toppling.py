"""Common (block-flexural) toppling of an excavated slope, after Nichol et al. (2002) (thesis
5.2.2, figs 5.6-5.10, tables 5.2 and 5.3).

Geometry (m), origin at the bottom-left corner, the slope facing +x (joints dipping into the
slope are ``dip_direction="left"``). Figure 5.6 is not in the text; what the words give is one
joint set dipping 80 degrees into the slope at 6, 3 or 1.5 m, flaws only in a zone near the
face, 12 excavation blocks that raise the slope, and a 40 m scale bar in fig 5.8. **Assumed**
(all in one place here, the module constants):

- the final slope: ``SLOPE_HEIGHT`` = 120 m with a 60 degree face (steeper than the 40 degree
  that interlayer slip needs: face dip > (90 - 80) + 30, Goodman & Bray 1976), on a
  ``BASE`` = 30 m thick base, ``CREST_LENGTH`` = 80 m of ground behind the crest and a
  ``TOE_LENGTH`` = 40 m toe bench (a 189 m x 150 m model: the slope is three 40 m scale bars
  high, as fig 5.8 suggests); ``ToppleParams.slope_height`` changes the height for a
  sensitivity run (the crest stays, the toe, lifts and points follow;
  benchmarks/trials/common_toppling_height.py);
- the ground before excavation is flat at the crest level; the 12 excavation blocks of fig
  5.6 are the 10 m lifts (``LIFT``) of rock in front of the final face, numbered from the top
  (``lift1`` .. ``lift12``), so after k lifts the slope is 10 k m high with the final face's
  upper part (the thesis's "the slope was excavated block by block ... the height of the slope
  was increased gradually");
- the joints cut the whole model (lifts, zone, rock behind), one of them half a spacing behind
  the toe (a joint through the toe corner would cut a sliver off it);
- the flaws (Voronoi cells of edge ``edge_length``) fill the zone within ``zone_depth``
  (normal) of the final face between the toe and crest levels (fig 5.6's dark area,
  ``dem_core.geometry.zone_polygon_along_face``). In the lifts the joints cut the rock into
  column pieces with no cross flaws (they are removed; the lift boundaries are intact rock).
  Behind the zone the thesis had no flaws (its "flaws ... were generated inside this zone ...
  not to study the extension of toppling at the back of the slope") but UDEC's zoned blocks
  bend; rigid blocks do not, and rigid columns 150 m long would prop the zone (measured on the
  quick 6 m model, all lifts removed at once: crest 21 mm with rigid columns, 184 mm with the
  cells below). So the rock behind the zone is cut into coarse Voronoi cells
  (``back_edge``, 6 m) glued by **unbreakable** "flaw:rock" contacts of the intact rock's
  stiffness: the columns bend there but cannot break (regular cuts normal to the joints were
  tried first; they left slivers at the left side, one of which made a run unstable). The
  region boundaries (zone | rock, lift | lift, lift | zone) are intact rock, breakable, with
  the flaws' strength;
- boundaries: fixed base, rollers on both sides (``CENTRIFUGE_BOUNDARIES``: the usual
  plane-strain slope box); gravity only (no in-situ stress is given);
- points ``crest`` (1 m below the crest, 2 m behind its edge: fig 5.9's "top of the slope")
  and ``toe`` (1 m above and 2 m behind the toe: "the toe of the slope").

Materials (table 5.2 and 5.3, SI): blocks E 20 GPa, nu 0.25, density 2650 kg/m3
(**assumed**: not given). Intact rock (the ``"*"`` pattern: flaws and region boundaries)
kn 40, ks 20 GPa/m with the study's friction, cohesion and tensile strength; the bedding joints
(``"joint:*"``) friction 30, c 0, T 0, kn 10, ks 1 GPa/m. The thesis brought the model to
equilibrium under gravity with "high strength values" first: the scene's intact rock starts
at ``GRAVITY_STRENGTH`` (a ``change_material`` stage then gives the study's values, see
``comparisons/common_toppling.py``). Conventional mode (the thesis's conventional UDEC without
the cross joints Nichol et al. placed): the same scene with the intact rock unbreakable.
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
from dem_core.workflow.scene import Scene

from . import CENTRIFUGE_BOUNDARIES, CENTRIFUGE_GROUPS, old_param_names

SLOPE_HEIGHT, FACE_DIP, BASE = 120.0, 60.0, 30.0        # m, deg, m
CREST_LENGTH, TOE_LENGTH = 80.0, 40.0                   # m
N_LIFTS = 12
LIFT = SLOPE_HEIGHT / N_LIFTS                           # 10 m
JOINT_DIP = 80.0                                        # into the slope, deg
DENSITY = 2650.0                                        # kg/m3 (assumed)
CREST_X = CREST_LENGTH                                  # the crest's x at every height
# Gravity equilibrium before the study's strengths (thesis: "high strength values"): Pa, deg.
GRAVITY_STRENGTH = dict(tensile_strength=50e6, cohesion=50e6, friction=45.0)
SPACINGS = (6.0, 3.0, 1.5)


@old_param_names
@dataclass(frozen=True)
class ToppleParams:
    """The scene's parameters (SI, degrees); defaults: the 6 m model with table 5.2."""

    spacing: float = 6.0                     # joint spacing (layer thickness), m
    edge_length: float = 1.0                 # Voronoi flaw edge, m
    zone_depth: float = 30.0                 # zone of flaws, normal to the face, m
    back_edge: float = 6.0                   # glued cells behind it (columns bend), m
    slope_height: float = SLOPE_HEIGHT       # final slope, m (fig 5.6's is not given)
    relax_iterations: int = 20
    seed: int = 1
    flaw_friction: float = 30.0
    flaw_cohesion: float = 5e6
    flaw_tensile_strength: float = 1e6
    flaw_kn: float = 40e9
    flaw_ks: float = 20e9
    joint_friction: float = 30.0
    joint_kn: float = 10e9
    joint_ks: float = 1e9
    block_E: float = 20e9
    block_nu: float = 0.25
    conventional: bool = False

    def __post_init__(self):
        for name in ("spacing", "edge_length", "zone_depth", "back_edge", "slope_height",
                     "flaw_kn", "flaw_ks", "joint_kn", "joint_ks", "block_E"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
        for name in ("flaw_cohesion", "flaw_tensile_strength"):
            v = getattr(self, name)
            if not (math.isfinite(v) and 0 <= v <= GRAVITY_STRENGTH[_FIELD[name]]):
                raise ValueError(f"{name} must be in [0, {GRAVITY_STRENGTH[_FIELD[name]]:g}] "
                                 f"Pa (the gravity stage's strength), got {v!r}")
        for name in ("flaw_friction", "joint_friction"):
            if not 0 <= getattr(self, name) < 90:
                raise ValueError(f"{name} must be in [0, 90) degrees, got "
                                 f"{getattr(self, name)!r}")
        if self.edge_length > self.spacing:
            raise ValueError(f"edge_length {self.edge_length} m must not exceed the joint "
                             f"spacing {self.spacing} m (no flaw across a layer)")
        if not self.zone_depth < CREST_LENGTH * math.sin(math.radians(FACE_DIP)):
            raise ValueError(f"zone_depth {self.zone_depth} m leaves the model (crest "
                             f"{CREST_LENGTH} m)")
        if not 0 < self.block_nu < 0.5:
            raise ValueError(f"block_nu must be in (0, 0.5), got {self.block_nu!r}")

    def with_(self, **changes) -> "ToppleParams":
        return replace(self, **changes)

    def intact_strength(self) -> dict:
        """The study's intact-rock strength as ``Material`` fields (Pa, deg)."""
        return dict(tensile_strength=self.flaw_tensile_strength, cohesion=self.flaw_cohesion,
                    friction=self.flaw_friction)


_FIELD = {"flaw_cohesion": "cohesion", "flaw_tensile_strength": "tensile_strength"}


# Every function of the section below takes ``slope`` (m), the final slope's height: the
# scene's ``ToppleParams.slope_height``, ``SLOPE_HEIGHT`` unless a sensitivity run changes it.
# The crest stays at x = CREST_LENGTH; the toe, the width and the top move with it.

def slope_region(slope: float = SLOPE_HEIGHT) -> Region:
    """The final slope as one Region (what the continuum meshes, without the lifts)."""
    return slope_profile(slope, FACE_DIP, CREST_LENGTH, TOE_LENGTH, BASE, name="rock")


def profile(slope: float = SLOPE_HEIGHT) -> list:
    """The final slope section (m), counter-clockwise from the bottom-left corner."""
    return [tuple(map(float, xy)) for xy in slope_region(slope).exterior]


def face(slope: float = SLOPE_HEIGHT):
    """The final face as ((x_toe, y_toe), (x_crest, y_crest)), m."""
    return (x_face(BASE, slope), BASE), (CREST_X, BASE + slope)


def face_at(height: float, slope: float = SLOPE_HEIGHT):
    """The face of the slope once ``height`` m of it are excavated (lifts removed down to
    the top - height), as ((x_toe, y_toe), (x_crest, y_crest)), m."""
    top = BASE + slope
    return (x_face(top - height, slope), top - height), (CREST_X, top)


def x_face(y: float, slope: float = SLOPE_HEIGHT) -> float:
    """x of the final face at level y (m)."""
    return CREST_X + (BASE + slope - y) / math.tan(math.radians(FACE_DIP))


def lift_name(k: int) -> str:
    return f"lift{k}"


def lift(k: int, slope: float = SLOPE_HEIGHT) -> Region:
    """Excavation block k (1 = top): the rock in front of the final face between
    top - k lift and top - (k - 1) lift (a lift is slope / N_LIFTS high)."""
    top, dy = BASE + slope, slope / N_LIFTS
    width = x_face(BASE, slope) + TOE_LENGTH
    y0, y1 = top - k * dy, top - (k - 1) * dy
    return Region(lift_name(k), [(x_face(y0, slope), y0), (width, y0), (width, y1),
                                 (x_face(y1, slope), y1)])


def height_after(k: int, slope: float = SLOPE_HEIGHT) -> float:
    """Slope height (m) after excavating lifts 1..k."""
    return k * slope / N_LIFTS


def monitoring_points(slope: float = SLOPE_HEIGHT) -> dict:
    """``crest`` and ``toe`` (module docstring), m."""
    (tx, _), (cx, top) = face(slope)
    return {"crest": (cx - 2.0, top - 1.0), "toe": (tx - 2.0, BASE + 1.0)}


def regions(p: ToppleParams) -> list:
    """The zone of flaws, the rock behind it (``rock``) and the 12 lifts."""
    rock = slope_region(p.slope_height)
    zone = Polygon(zone_polygon_along_face(rock, p.zone_depth))
    behind = shapely.orient_polygons(rock.polygon().difference(zone))
    out = [Region("zone", np.asarray(shapely.orient_polygons(zone).exterior.coords)[:-1]
                  .tolist()),
           Region("rock", np.asarray(behind.exterior.coords)[:-1].tolist())]
    return out + [lift(k, p.slope_height) for k in range(1, N_LIFTS + 1)]


def joint_set(p: ToppleParams) -> JointSet:
    return JointSet("bedding", JOINT_DIP, p.spacing, dip_direction="left",
                    origin=face(p.slope_height)[0],
                    offset=0.5 * p.spacing)


def geometry(p: ToppleParams) -> GeometrySpec:
    """The regions, the bedding joints, the zone's flaws and the coarse cells behind it
    (``back_edge``; their edges are the "flaw:rock" contacts ``materials`` keeps elastic)."""
    vor = {"zone": Voronoi(edge_length=p.edge_length, relax_iterations=p.relax_iterations,
                           seed=p.seed),
           "rock": Voronoi(edge_length=p.back_edge, relax_iterations=p.relax_iterations,
                           seed=p.seed + 1)}
    return GeometrySpec(regions(p), joint_sets=[joint_set(p)], voronoi=vor)


def materials(p: ToppleParams) -> dict:
    """Intact rock ``"*"`` (at ``GRAVITY_STRENGTH``; unbreakable in conventional mode) and the
    bedding joints ``"joint:*"``."""
    intact = Material(kn=p.flaw_kn, ks=p.flaw_ks, breakable=not p.conventional,
                      **GRAVITY_STRENGTH)
    joint = Material(kn=p.joint_kn, ks=p.joint_ks, tensile_strength=0.0, cohesion=0.0,
                     friction=p.joint_friction)
    elastic = replace(intact, breakable=False)       # the columns behind the zone bend only
    return {"*": intact, "flaw:rock": elastic, "joint:*": joint}


# Local damping 0.8 (UDEC's default, as examples/field_slope.py): with kinetic damping the
# unbalanced ratio of this model stalled at 1e-3 - 1e-2 over 60,000 steps after the gravity
# and excavation solves, with local damping it reaches 1e-5 in 3,000 - 30,000 (measured on
# the 6 m model at 3 m flaws, 2026-11-25).
# The library's contact model, edge elements on the rigid blocks (2026-12-01): the columns
# topple by bending, and end springs give a bonded edge about 3 x its beam bending strength
# (benchmarks/column_bending.py). End springs before: {"edge_elements": false}.
SOLVER = {"new_contact_material": "joint:bedding", "mass_scaling": True, "damping": 0.8}


def scene(p: ToppleParams, stages=()) -> Scene:
    """The scene as data: geometry, materials, a fixed base with rollers on the sides, the
    crest and toe points, the quasi-static solver (``SOLVER``) and ``stages``
    (``comparisons.common_toppling``)."""
    return Scene(geometry(p), materials(p), density=DENSITY, block_E=p.block_E,
                 block_nu=p.block_nu, groups=CENTRIFUGE_GROUPS,
                 boundaries=CENTRIFUGE_BOUNDARIES, points=monitoring_points(p.slope_height),
                 stages=list(stages), solver=dict(SOLVER), name="common_toppling")
