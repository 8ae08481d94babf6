"""Lab specimens of thesis chapter 3 (sections 3.5-3.8, Table 3.1): plaster of Paris after
Lajtai (1969).

Three scenes, each a Voronoi specimen ("rock") between rigid loading parts (one block each):

- ``ucs_specimen``: a 2:1 specimen between a bottom and a top platen (unconfined compression,
  and the direct tension test with the platens glued and pulled apart);
- ``shear_specimen``: a direct-shear specimen in a split box, the shear plane at mid-height,
  optionally with joints at each end of the shear plane: open (rectangular voids, Lajtai's
  tests and thesis fig. 3.10), or closed (frictional joint lines; thesis figs 3.12-3.13).

Sizes are shown only in the thesis figures (3.8, 3.10, 3.13); **assumptions** (stated in the
results' notes too):

- UCS specimen 100 mm wide x 200 mm high (2:1; thesis 3.5: "a two-to-one model ... edge length
  of 7 mm"), platens 1 edge length thick and as wide as the specimen. About 14 blocks across
  at 7 mm: with 5 blocks across (60 mm) the rigid-block specimen never softened.
- Direct-shear specimen 150 mm long x 75 mm high, shear plane at y = 37.5 mm. The lower box
  is a bottom plate and two walls up to 1/6 of the height below the shear plane, the upper box
  a top plate and two walls from 1/6 of the height above it (the gap lets the plane form
  freely). Joints start at both ends of the plane and run inwards, each k L / 2 long, so the
  persistence is k = joint length / sheared length (thesis 3.6, fig. 3.13).
- Open joints are slots 2 mm high (the voids of Lajtai's specimens; the thesis's 0.1 mm is the
  UDEC joint aperture, below the block scale).
- Lajtai's open- and closed-joint specimens are taken with k = 0.5 (two 37.5 mm joints, a 75 mm
  central bridge); the persistence study varies k.

Contacts between the specimen and the loading parts (``boundary:*`` materials):

- platens in compression: unbonded, friction 5 degrees ("lubricated" platens: the ends expand
  almost freely, so the specimen sees nearly uniaxial stress; the specimen cannot drift);
- platens in tension and the box plates in shear: glued (``breakable=False``), the stiffness of
  the flaws (the specimen is cast into the box);
- box walls: unbonded and frictionless, so the walls push in x only and the whole normal load
  goes through the plates.

Units SI (m, Pa, kg/m^3); friction in degrees.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from comparisons import lab
from dem_core.geometry import (GeometrySpec, JointLine, Region, Voronoi, build_block_system,
                               rectangle)
from dem_core.contact.materials import Material
from dem_core.workflow.scene import Boundary, Scene
from dem_core.workflow.scene import build_model as build_scene_model

# Thesis Table 3.1 (plaster of Paris) and 3.5.
THESIS_TENSILE = 1.1e6
THESIS_FRICTION = 37.0
THESIS_COHESION = 1.2e6          # back-calculated from UCS 4.1 MPa
THESIS_UCS = 4.1e6
THESIS_KN = 40e9
THESIS_KS = 20e9
THESIS_BLOCK_E = 4.5e9
THESIS_EDGE = 0.007
# Not in the thesis: set plaster of Paris (dry) about 1200 kg/m^3; Poisson ratio of the blocks 0.25.
DENSITY = 1200.0
BLOCK_NU = 0.25

UCS_WIDTH, UCS_HEIGHT = 0.100, 0.200
SHEAR_LENGTH, SHEAR_HEIGHT = 0.150, 0.075
SLOT_HEIGHT = 0.002
LAJTAI_PERSISTENCE = 0.5
PLATEN_FRICTION = 5.0


@dataclass(frozen=True)
class FlawParams:
    """Flaw (intact-rock contact) properties and the Voronoi block size.

    Attributes: ``edge_length`` (m), ``tensile``, ``cohesion`` (Pa), ``friction`` (deg),
    ``kn``, ``ks`` (Pa/m), ``block_E`` (Pa, None = rigid blocks), ``block_nu``,
    ``relax_iterations``, ``seed``. Defaults: thesis Table 3.1 at 7 mm.
    """

    edge_length: float = THESIS_EDGE
    tensile: float = THESIS_TENSILE
    cohesion: float = THESIS_COHESION
    friction: float = THESIS_FRICTION
    kn: float = THESIS_KN
    ks: float = THESIS_KS
    block_E: float | None = THESIS_BLOCK_E
    block_nu: float = BLOCK_NU
    relax_iterations: int = 30
    seed: int = 1

    def with_(self, **changes) -> "FlawParams":
        return replace(self, **changes)

    def flaw(self) -> Material:
        return Material(kn=self.kn, ks=self.ks, tensile_strength=self.tensile,
                        cohesion=self.cohesion, friction=self.friction)

    def voronoi(self) -> Voronoi:
        return Voronoi(edge_length=self.edge_length, relax_iterations=self.relax_iterations,
                       seed=self.seed)


# ---------------------------------------------------------------------------- UCS / tension
def ucs_geometry(p: FlawParams, width=UCS_WIDTH, height=UCS_HEIGHT) -> GeometrySpec:
    """Specimen [0, width] x [0, height] with platens below and above (groups = region names
    ``platen_bottom``, ``platen_top``)."""
    t = p.edge_length
    return GeometrySpec(
        regions=[rectangle("rock", 0.0, 0.0, width, height),
                 rectangle("platen_bottom", 0.0, -t, width, 0.0),
                 rectangle("platen_top", 0.0, height, width, height + t)],
        voronoi={"rock": p.voronoi()})


def ucs_materials(p: FlawParams, glued_platens: bool) -> dict:
    """Flaws, and the platen contacts: lubricated (compression) or glued (tension)."""
    if glued_platens:
        platen = Material(kn=p.kn, ks=p.ks, breakable=False)
    else:
        platen = Material(kn=p.kn, ks=p.ks, friction=PLATEN_FRICTION)
    return {"flaw:*": p.flaw(), "boundary:*": platen}


# ---------------------------------------------------------------------------- direct shear
@dataclass(frozen=True)
class ShearParams:
    """A direct-shear specimen: ``joints`` "none" | "open" | "closed", persistence ``k``
    (joint length / shear-plane length, joints at both ends), joint friction (deg), size (m)."""

    joints: str = "none"
    k: float = 0.0
    joint_friction: float = THESIS_FRICTION
    length: float = SHEAR_LENGTH
    height: float = SHEAR_HEIGHT
    slot_height: float = SLOT_HEIGHT

    def __post_init__(self):
        if self.joints not in ("none", "open", "closed"):
            raise ValueError(f"joints must be 'none', 'open' or 'closed', got {self.joints!r}")
        if not 0.0 <= self.k <= 1.0:
            raise ValueError(f"persistence k must be in [0, 1], got {self.k!r}")
        if self.joints == "open" and self.k >= 1.0:
            raise ValueError("open joints with k = 1 leave no specimen: use closed joints")
        if self.joints == "none" and self.k > 0:
            raise ValueError(f"k = {self.k} given with joints='none'")


def _slotted_outline(s: ShearParams, a: float):
    """Specimen outline with a slot of length ``a`` cut in from each end of the shear plane."""
    L, H, y0, y1 = s.length, s.height, 0.5 * (s.height - s.slot_height), \
        0.5 * (s.height + s.slot_height)
    return [(0, 0), (L, 0), (L, y0), (L - a, y0), (L - a, y1), (L, y1), (L, H), (0, H),
            (0, y1), (a, y1), (a, y0), (0, y0)]


def shear_geometry(p: FlawParams, s: ShearParams) -> GeometrySpec:
    """The specimen and the split box; groups ``box_low`` and ``box_up`` (module docstring)."""
    L, H, t = s.length, s.height, p.edge_length
    yc = 0.5 * H
    gap = H / 6.0
    a = 0.5 * s.k * L                                # joint length at each end
    joints = []
    if s.joints == "open" and a > 0:
        rock = Region("rock", _slotted_outline(s, a))
        gap = max(gap, 0.5 * s.slot_height + 0.5 * t)
    else:
        rock = Region("rock", [(0, 0), (L, 0), (L, H), (0, H)])
        if s.joints == "closed" and a > 0:
            if s.k >= 1.0:
                joints = [JointLine("joint", [(0.0, yc), (L, yc)], regions=["rock"])]
            else:
                joints = [JointLine("left", [(0.0, yc), (a, yc)], regions=["rock"]),
                          JointLine("right", [(L - a, yc), (L, yc)], regions=["rock"])]
    regions = [rock,
               rectangle("plate_low", 0.0, -t, L, 0.0, groups=["box_low"]),
               rectangle("wall_low_left", -t, 0.0, 0.0, yc - gap, groups=["box_low"]),
               rectangle("wall_low_right", L, 0.0, L + t, yc - gap, groups=["box_low"]),
               rectangle("plate_up", 0.0, H, L, H + t, groups=["box_up"]),
               rectangle("wall_up_left", -t, yc + gap, 0.0, H, groups=["box_up"]),
               rectangle("wall_up_right", L, yc + gap, L + t, H, groups=["box_up"])]
    return GeometrySpec(regions=regions, joints=joints, voronoi={"rock": p.voronoi()})


def shear_materials(p: FlawParams, s: ShearParams) -> dict:
    """Flaws; joints (T = c = 0, the flaw stiffness, thesis 3.6); glued plates; smooth walls."""
    return {"flaw:*": p.flaw(),
            "joint:*": Material(kn=p.kn, ks=p.ks, friction=s.joint_friction),
            "boundary:*": Material(kn=p.kn, ks=p.ks, friction=0.0),
            "boundary:rock|plate_*": Material(kn=p.kn, ks=p.ks, breakable=False)}


def build(spec: GeometrySpec):
    """The block system of a scene (thin wrapper so callers need not import dem_core)."""
    return build_block_system(spec)


def stiffness_for_edge(p: FlawParams, edge: float) -> FlawParams:
    """``p`` at block edge ``edge`` with kn, ks scaled by thesis eq. 3.7 (kn proportional to
    1 / zone width, so kn(edge) = kn(p.edge_length) p.edge_length / edge; ks/kn kept)."""
    f = p.edge_length / edge
    return p.with_(edge_length=edge, kn=p.kn * f, ks=p.ks * f)


def _solver(safety=0.5) -> dict:
    """Solver options shared by the lab scenes: quasi-static (mass scaling, local damping 0.8);
    the blocks are deformable in series with the contacts (the scenes' block_E, block_nu). The
    contacts are the end-spring pair of the thesis's UDEC: on edge elements the rigid specimen's
    peak at low flaw cohesion is not quasi-static (docs/cases/lajtai.md, "The UCS floor on edge
    elements")."""
    return dict(mass_scaling=True, damping=0.8, safety=safety, edge_elements=False)


def ucs_scene(p: FlawParams, width=UCS_WIDTH, height=UCS_HEIGHT, glued_platens=False,
              safety=0.5, rate=None, max_strain=None) -> Scene:
    """The compression (or, glued, tension) specimen between its platens as a scene: the lower
    platen fixed; groups "left side", "right side" (specimen blocks on its side faces: the
    lateral gauge). With ``rate`` (m/step) and ``max_strain`` its stage is the loading path
    (``comparisons.lab.compression_load`` or ``tension_load``)."""
    groups = {"left edge": {"touching": "left"}, "right edge": {"touching": "right"},
              "platens": {"union": ["platen_bottom", "platen_top"]},
              "left side": {"minus": ["left edge", "platens"]},
              "right side": {"minus": ["right edge", "platens"]}}
    stages = []
    if rate is not None:
        stages = [lab.tension_load(width, height, rate, max_strain) if glued_platens else
                  lab.compression_load(width, height, rate, ("left side", "right side"),
                                       max_strain)]
    return Scene(ucs_geometry(p, width, height), ucs_materials(p, glued_platens),
                 density=DENSITY, block_E=p.block_E, block_nu=p.block_nu, groups=groups,
                 boundaries=[Boundary("platen_bottom")], stages=stages, solver=_solver(safety),
                 name="lajtai ucs" if not glued_platens else "lajtai tension")


def ucs_model(p: FlawParams, width=UCS_WIDTH, height=UCS_HEIGHT, glued_platens=False,
              safety=0.5, blocks=None):
    """The compression (or, glued, tension) specimen as a Model (built from ``ucs_scene``)."""
    sc = ucs_scene(p, width, height, glued_platens, safety)
    return build_scene_model(sc, build(sc.geometry) if blocks is None else blocks)


def shear_scene(p: FlawParams, s: ShearParams, safety=0.5, normal_stress=None, rate=None,
                max_displacement=None) -> Scene:
    """The direct-shear specimen in its box as a scene: the lower box fixed; new contacts get
    the flaws' residual strength. With ``normal_stress`` (Pa), ``rate`` (m/step) and
    ``max_displacement`` (m) its stages are the loading path (``comparisons.lab.shear_stages``:
    the upper box servo-pressed, the lower box moved)."""
    stages = [] if rate is None else lab.shear_stages(s.length, normal_stress, rate,
                                                       max_displacement)
    return Scene(shear_geometry(p, s), shear_materials(p, s), density=DENSITY,
                 block_E=p.block_E, block_nu=p.block_nu, boundaries=[Boundary("box_low")],
                 stages=stages, solver=dict(_solver(safety), new_contact_material="flaw:rock"),
                 name="lajtai direct shear")


def shear_model(p: FlawParams, s: ShearParams, safety=0.5, blocks=None):
    """The direct-shear specimen in its box as a Model (built from ``shear_scene``)."""
    sc = shear_scene(p, s, safety)
    return build_scene_model(sc, build(sc.geometry) if blocks is None else blocks)
