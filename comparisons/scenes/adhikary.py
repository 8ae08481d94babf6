"""Adhikary & Dyskin (2006) centrifuge model IGM-01 (thesis section 4.2, Table 4.1).

Geometry (m), origin at the bottom-left corner of the model, the slope facing +x (the
toolkit's convention: joints dipping into the slope are ``dip_direction="left"``):

- the model is 0.400 m wide and 0.395 m high (thesis fig. 4.12); the slope is 0.330 m high with
  a 61 degree face, so the base below the toe is 0.065 m thick;
- **assumption (fig)**: the crest runs from x = 0 to the crest edge at x = 0.217 m and the face
  goes down to the toe at the model's right side, x = 0.400 m, on top of the 65 mm base (no
  toe bench; ``TOE_BENCH`` holds the bench length if the figure shows one);
- bedding joints dip 81 degrees into the slope (the thesis's DM model; 80 in the experiment) at
  10 mm spacing and cut the whole model, base included ("40 beds across base", fig. 4.4);
- Voronoi flaws fill the columns (block edge ``edge_length``);
- **assumption (fig 4.8)**: fixed base (the blocks touching y = 0), rollers on both sides (the
  blocks touching x = 0 and x = 0.4 hold x, free in y and rotation);
- **assumption (fig 4.2 insert)**: point A on the crest 5 mm behind the crest edge and 2 mm
  below the crest surface; point B on the face at mid-height, 2 mm inside the rock. Positive
  horizontal displacement is out of the slope (+x).

Materials (thesis Table 4.1, section 4.2.3): blocks E 2.6 GPa, nu 0.16, unit weight 23.8
kN/m3; flaws kn 700, ks 600 GPa/m, T 1.1 MPa, c 1.6 MPa, friction 37; bedding c 15 kPa,
friction 23, T 0 (not given in the thesis: UDEC's default; ``bedding_tensile`` sets another, Pa) and, after a tensile or shear
failure, friction only (the thesis's residual c = T = 0; ``bedding_residual_cohesion``, Pa, keeps
some cohesion on slipped beds: a perfectly plastic bedding when equal to ``bedding_cohesion``).
**Assumption**: the bedding stiffness is not given; it is taken equal to the flaws' (the planes
of the model were glued and tight).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from dem_core.geometry import GeometrySpec, JointSet, Region, Voronoi, slope_profile
from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.workflow.scene import Scene
from dem_core.workflow.scene import build_model as build_scene_model
from dem_core.workflow.stages import RaiseGravity
from dem_core.units import STANDARD_GRAVITY

from . import CENTRIFUGE_BOUNDARIES, CENTRIFUGE_GROUPS, old_param_names

WIDTH, HEIGHT, SLOPE_HEIGHT, FACE_DIP, TOE_BENCH = 0.400, 0.395, 0.330, 61.0, 0.0
BASE = HEIGHT - SLOPE_HEIGHT
UNIT_WEIGHT = 23.8e3
DENSITY = UNIT_WEIGHT / STANDARD_GRAVITY


@old_param_names
@dataclass(frozen=True)
class AdhikaryParams:
    """The scene's parameters (SI units, angles in degrees); defaults are the thesis's base run."""

    edge_length: float = 0.004
    relax_iterations: int = 20
    seed: int = 1
    # False (default): random relaxed Voronoi cells split along the bed joints, like the
    # thesis's tessellation inside each bed. True: seed rows on both sides of every bed joint
    # (cell edges along the joints); in 10 mm beds those rows leave few or no random seeds at
    # 4-8 mm edges, a regular pattern the seed does not change (docs/comparisons.md)
    edge_seeding: bool = False
    joint_dip: float = 81.0
    joint_spacing: float = 0.010
    flaw_tensile_strength: float = 1.1e6
    flaw_cohesion: float = 1.6e6
    flaw_friction: float = 37.0
    flaw_kn: float = 700e9
    flaw_ks: float = 600e9
    # fracture energies of the flaws, J/m^2 (0: brittle, the thesis's law; Material)
    flaw_fracture_energy_I: float = 0.0
    flaw_fracture_energy_II: float = 0.0
    bedding_cohesion: float = 15e3
    bedding_tensile: float = 0.0
    bedding_residual_cohesion: float = 0.0
    bedding_friction: float = 23.0
    bedding_kn: float = 700e9
    bedding_ks: float = 600e9
    block_E: float = 2.6e9
    block_nu: float = 0.16
    conventional: bool = False
    # the section (m, degrees); defaults are the experiment's (other sizes: a family of
    # centrifuge slopes with the same joints and materials)
    slope_height: float = SLOPE_HEIGHT
    base_thickness: float = BASE
    width: float = WIDTH
    face_dip: float = FACE_DIP
    toe_bench: float = TOE_BENCH

    def with_(self, **changes) -> "AdhikaryParams":
        return replace(self, **changes)


def profile(p: AdhikaryParams | None = None) -> list:
    """The slope section (m), counter-clockwise from the bottom-left corner."""
    return [tuple(map(float, xy)) for xy in _region(p or AdhikaryParams()).exterior]


def _crest_x(p: AdhikaryParams) -> float:
    return p.width - p.toe_bench - p.slope_height / math.tan(math.radians(p.face_dip))


def _region(p: AdhikaryParams) -> Region:
    if _crest_x(p) <= 0:
        raise ValueError(f"width {p.width} m is too small for a {p.slope_height} m slope at "
                         f"{p.face_dip} degrees with a {p.toe_bench} m toe bench")
    return slope_profile(p.slope_height, p.face_dip, crest_length=_crest_x(p),
                         toe_length=p.toe_bench, base_thickness=p.base_thickness, name="rock")


def face(p: AdhikaryParams | None = None):
    """The free face as ((x_toe, y_toe), (x_crest, y_crest)), m."""
    p = p or AdhikaryParams()
    top = p.base_thickness + p.slope_height
    return (p.width - p.toe_bench, p.base_thickness), (_crest_x(p), top)


def monitoring_points(p: AdhikaryParams | None = None) -> dict:
    """Points A (crest) and B (mid-face), m (module docstring)."""
    p = p or AdhikaryParams()
    (tx, ty), (cx, cy) = face(p)
    t = math.radians(p.face_dip)
    inward = np.array([-math.sin(t), -math.cos(t)])          # into the rock, normal to the face
    mid = 0.5 * (np.array([tx, ty]) + np.array([cx, cy]))
    return {"A": (cx - 0.005, cy - 0.002), "B": tuple(mid + 0.002 * inward)}


def geometry(p: AdhikaryParams) -> GeometrySpec:
    rock = _region(p)
    bedding = JointSet("bedding", p.joint_dip, p.joint_spacing, dip_direction="left")
    vor = Voronoi(edge_length=p.edge_length, relax_iterations=p.relax_iterations, seed=p.seed,
                  edge_seeding=p.edge_seeding)
    return GeometrySpec([rock], joint_sets=[bedding], voronoi={"rock": vor})


def materials(p: AdhikaryParams) -> dict:
    flaw = Material(kn=p.flaw_kn, ks=p.flaw_ks, tensile_strength=p.flaw_tensile_strength,
                    cohesion=p.flaw_cohesion, friction=p.flaw_friction,
                    fracture_energy_I=p.flaw_fracture_energy_I,
                    fracture_energy_II=p.flaw_fracture_energy_II)
    bedding = Material(kn=p.bedding_kn, ks=p.bedding_ks, tensile_strength=p.bedding_tensile,
                       cohesion=p.bedding_cohesion, friction=p.bedding_friction,
                       residual_cohesion=p.bedding_residual_cohesion)
    return {"flaw:rock": flaw, "joint:bedding": bedding}


# the scene's solver (``scene``): quasi-static g-ramps, edge elements on the eigen step
SOLVER = {"mass_scaling": True, "damping": 0.0, "kinetic_damping": 100,
          "edge_elements": True, "step_estimate": "eigen"}


def scene(p: AdhikaryParams, stages=()) -> Scene:
    """The scene as data (``dem_core.workflow.scene``): geometry, materials, the centrifuge boundaries,
    points A and B, the quasi-static g-ramp solver (kinetic damping, mass scaling) and
    ``stages`` (e.g. one ``stages.RaiseGravity``).

    The contact model is the one whose failure g converges with block size: every shared edge
    a linear element (``edge_elements``: a bonded edge's bending stiffness and strength do not
    depend on the block size; 39.4 / 39.1 / 37.9 g at 6 / 4 / 3 mm, docs/cases/adhikary.md)
    on the step from the largest eigenvalue (``step_estimate="eigen"``). The end-spring pair
    UDEC uses, 3.8 times too strong in bending at 6 mm (benchmarks/column_bending.py), is
    ``{"edge_elements": False, "step_estimate": "bound"}`` over this solver."""
    solver = dict(SOLVER)
    if p.conventional:
        solver["unbreakable"] = "flaw:*"
    return Scene(geometry(p), materials(p), density=DENSITY, block_E=p.block_E,
                 block_nu=p.block_nu, groups=CENTRIFUGE_GROUPS,
                 boundaries=CENTRIFUGE_BOUNDARIES, points=monitoring_points(p), stages=list(stages),
                 solver=solver, name="adhikary")


def base_run() -> Scene:
    """The thesis's base run as a scene (the file ``adhikary.json`` next to this module): the
    default parameters (6 mm random cells, T = 1.1 MPa) raised from 10 g in 10 g levels, each
    failure bracket bisected to 1 g (the full variant's ramp, ``comparisons.adhikary``), each
    level judged by the response judge (``SolveSettings.judge``: at rest or a mechanism over
    windows of the slope's response time, no step budget)."""
    ramp = RaiseGravity(tuple(float(g) for g in range(10, 301, 10)), ratio=1e-5,
                        failure_displacement=0.005, creep=2e-4,
                        watch=("A", "B"), refine_to=1.0, judge="response")
    sc = scene(AdhikaryParams(edge_length=0.006, relax_iterations=10), stages=[ramp])
    sc.description = ("Adhikary & Dyskin (2006) centrifuge model IGM-01, the thesis's base run "
                      "(4.2): 0.33 m slope at 61 deg, 10 mm beds dipping 81 deg into it, 6 mm "
                      "Voronoi flaws T 1.1 MPa; fixed base, rollers on the sides; A crest, B "
                      "mid-face; g raised in 10 g levels, failures bisected to 1 g, each level "
                      "judged at rest or failing (response judge); shared edges as linear "
                      "elements. Geometry assumptions: comparisons/scenes/adhikary.py.")
    return sc


def build_model(p: AdhikaryParams, blocks=None, **model_options) -> Model:
    """The DEM model of the scene with its boundary conditions and points A and B
    (``dem_core.workflow.scene.build_model``; ``model_options`` override the scene's solver)."""
    return build_scene_model(scene(p), blocks, **model_options)
