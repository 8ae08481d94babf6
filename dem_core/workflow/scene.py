"""A scene as data: geometry, materials, groups, boundaries, monitoring points and stages.

One ``Scene`` (a JSON file, ``Scene.save`` / ``Scene.load``) is what both methods build from:
``build_model(scene)`` gives the DEM model with its boundaries and points,
``continuum_ref.from_scene`` the continuum model of the same slope; ``stages.run_stages`` runs
its stages. SI units inside (m, Pa, kg/m^3, Pa/m); angles in degrees, as the rest of the API.
docs/scenes.md shows a scene file and the same scene in Python.

Groups are data too, each one selector (``GROUP_SELECTORS``)::

    {"touching": "bottom"}              blocks with a vertex on a side of the model's box
    {"region": "rock"}                  blocks of a region (or a geometry group)
    {"inside": [[x, y], ...]}           blocks whose centroid lies in a polygon
    {"union": ["a", "b"]}               blocks in any of the named groups
    {"minus": ["a", "b"]}               blocks of group a that are not in group b

A boundary fixes velocity components of a group at zero: ``{"group": "sides", "x": true,
"y": false, "rotation": false}`` is a roller (in the continuum: the displacement components).
"""
from __future__ import annotations

import dataclasses
import difflib
import json
import math
import numbers
import re
from dataclasses import dataclass, field

import numpy as np
import shapely

from ..geometry import GeometrySpec
from ..geometry.regions import check_fields, check_keys
from ..settings import SCENE_SOLVER_KEYS, SolverOptions
from ..contact.materials import Material, material_for, material_table
from ..deformable.zone_plasticity import new_keys
from . import plausibility
from .stages import AFTER_FAILURE, STAGE_KINDS, check_stages, stage_from_dict, stage_to_dict

__all__ = ["Scene", "Boundary", "build_model", "conventional", "resolve_groups", "group_sides",
           "GROUP_SELECTORS"]

GROUP_SELECTORS = ("touching", "region", "inside", "union", "minus")
SIDES = ("bottom", "top", "left", "right")
_SCENE_KEYS = {"name", "description", "geometry", "materials", "density", "block_E",
               "block_nu", "groups", "boundaries", "points", "stages", "solver",
               "after_failure", "continuum"}
# the kind of each top-level value of a scene file (``Scene.from_dict``)
_SCENE_KINDS = {"name": str, "description": str, "materials": dict, "groups": dict,
                "boundaries": list, "points": dict, "stages": list, "solver": dict,
                "geometry": dict, "after_failure": str, "continuum": dict}
# Model options a scene may set: the SolverOptions fields but the block moduli (the scene's
# own top-level keys)
SOLVER_KEYS = set(SCENE_SOLVER_KEYS)
# The optional "continuum" section (``check_continuum``): mesh size h (m), the rock-mass
# material of each region (name or fnmatch pattern -> {"kind": ..., fields}) and the flow rule
# of a factor of safety (``continuum_ref.ssr``); ``continuum_ref.scene_run`` runs it.
CONTINUUM_KEYS = ("h", "materials", "flow", "refine", "search_step")
# "search_step" (optional): {"g": g, "F": F}, the first and largest step of the continuum's
# critical-g and factor-of-safety searches (continuum_ref.scene_run)
SEARCH_STEP_KEYS = ("g", "F")
# "refine" (optional): a graded mesh, h within d_near (m) of any of the points [[x, y], ...],
# growing linearly to h_far (m) at d_far (continuum_ref.mesh.refine_near)
REFINE_KEYS = ("points", "h_far", "d_near", "d_far")
CONTINUUM_FLOWS = ("native", "davis")
# kind -> (fields it takes, fields it needs); units: E, cohesion, tensile_strength, sci,
# sigma3_max Pa; friction, dilation degrees; h m. A Hoek-Brown rock mass is given by gsi, mi
# (and D) or by mb, s, a and E; sigma3_max (and dilation) make its equivalent Mohr-Coulomb for
# a factor of safety (``continuum_ref.materials.HoekBrown.equivalent_mohr_coulomb``).
CONTINUUM_MATERIALS = {
    "elastic": (("E", "nu"), ("E", "nu")),
    "mohr_coulomb": (("E", "nu", "cohesion", "friction", "dilation", "tensile_strength"),
                     ("E", "nu", "cohesion", "friction")),
    "hoek_brown": (("E", "nu", "sci", "gsi", "mi", "D", "mb", "s", "a", "sigma3_max",
                    "dilation"), ("sci",)),
    # from the region's own joints, flaws and blocks, at a stated bound ("joints" or
    # "intact"): continuum_ref.rock_mass
    "dem_rock_mass": (("bound", "dilation"), ("bound",)),
}
DEM_ROCK_MASS_BOUNDS = ("joints", "intact")     # continuum_ref.rock_mass.BOUNDS


@dataclass(frozen=True)
class Boundary:
    """Fixed velocity components (x, y, rotation) of a group, m/s = 0."""

    group: str
    x: bool = True
    y: bool = True
    rotation: bool = True


@dataclass
class Scene:
    """A slope, specimen or any model as data (module docstring).

    geometry : GeometrySpec. materials : name or fnmatch pattern -> Material (contact
    materials "flaw:<region>", "joint:<name>", "boundary:<A>|<B>"). density : kg/m^3.
    block_E, block_nu : block modulus (Pa, None: rigid) and Poisson ratio. groups : name ->
    selector. boundaries : list of Boundary. points : name -> (x, y) m. stages : stage records
    (``stages.py``). solver : Model options (``SOLVER_KEYS``). after_failure : "stop" (the
    stages after one that leaves the model failed or undecided do not run,
    ``stages.run_stages``) or "continue". continuum : what the continuum needs to run the
    scene (``continuum_ref.scene_run``): {"h": mesh size (m), "materials": {region name or
    pattern: {"kind": "elastic", "mohr_coulomb", "hoek_brown" or "dem_rock_mass", fields}},
    "flow": "native" or "davis", optionally "refine": {"points": [[x, y], ...], "h_far",
    "d_near", "d_far"} for a mesh graded from h near the points to h_far and "search_step":
    {"g": g, "F": F}, the first and largest step of the critical-g and factor-of-safety
    searches} (``check_continuum``, docs/scenes.md); None: DEM only.
    """

    geometry: GeometrySpec
    materials: dict
    density: float
    block_E: float | None = None
    block_nu: float = 0.25
    groups: dict = field(default_factory=dict)
    boundaries: list = field(default_factory=list)
    points: dict = field(default_factory=dict)
    stages: list = field(default_factory=list)
    solver: dict = field(default_factory=dict)
    name: str = "scene"
    description: str = ""
    after_failure: str = "stop"
    continuum: dict | None = None

    def __post_init__(self):
        self.boundaries = [b if isinstance(b, Boundary) else _boundary(b, i)
                           for i, b in enumerate(self.boundaries)]
        self.points = {k: _point(k, v) for k, v in self.points.items()}
        zs = self.solver.get("zone_strength")
        if isinstance(zs, dict):       # old key names (``zone_plasticity.OLD_KEYS``) renamed
            self.solver = dict(self.solver, zone_strength={
                k: new_keys(row, f"zone_strength[{k!r}]") if isinstance(row, dict) else row
                for k, row in zs.items()})
        self.validate()

    # ------------------------------------------------------------------ checks
    def validate(self) -> None:
        """Raise ValueError naming the bad item; nothing is computed before this passes."""
        check_name(self.name)
        _positive("density (kg/m^3)", self.density)
        if self.block_E is not None:
            _positive("block_E (Pa)", self.block_E)
        if not (_number(self.block_nu) and -1.0 < float(self.block_nu) < 0.5):
            raise ValueError(f"block_nu must be a number in (-1, 0.5), got {self.block_nu!r}")
        if self.after_failure not in AFTER_FAILURE:
            raise ValueError(f"after_failure must be one of {AFTER_FAILURE}, got "
                             f"{self.after_failure!r}")
        check_keys(self.solver, SOLVER_KEYS, "solver")
        check_fields(self.solver, SolverOptions, "solver", partial=True)
        for name in contact_material_names(self.geometry):
            material_table([name], self.materials)        # names the missing material
        plausibility.check_stiffness(self.materials)
        known = self.group_names()
        earlier = known - set(self.groups)          # a group may use the ones before it
        for gname, sel in self.groups.items():
            _check_selector(gname, sel, earlier)
            earlier.add(gname)
        for i, b in enumerate(self.boundaries):
            _check_boundary(b, i)
            if b.group not in known:
                raise ValueError(f"boundary on unknown group {b.group!r}; groups are "
                                 f"{sorted(known)}")
        for pname, xy in self.points.items():
            if not all(math.isfinite(v) for v in xy):
                raise ValueError(f"monitoring point {pname!r} is not finite: {xy!r}")
        _points_in_regions(self)
        for i, st in enumerate(self.stages):      # a stage's scalars of the right kind
            kind = _KIND_OF.get(type(st))
            if kind is not None:
                check_fields({f.name: getattr(st, f.name) for f in dataclasses.fields(st)},
                             type(st), f"stage {i} ({kind})")
        check_stages(self.stages, known, self.materials)
        if self.continuum is not None:
            check_continuum(self.continuum, [r.name for r in self.geometry.regions])

    def group_names(self) -> set:
        """Every group a boundary or stage may name: the scene's, the regions', the geometry's
        groups and the regions' extra groups."""
        g = self.geometry
        names = set(self.groups) | {r.name for r in g.regions} | set(g.groups)
        for r in g.regions:
            names |= set(r.groups)
        return names

    # ------------------------------------------------------------------ files
    def to_dict(self) -> dict:
        out = {"name": self.name, "description": self.description,
                "geometry": self.geometry.to_dict(),
                "materials": {k: dataclasses.asdict(m) for k, m in self.materials.items()},
                "density": self.density, "block_E": self.block_E, "block_nu": self.block_nu,
                "groups": self.groups,
                "boundaries": [dataclasses.asdict(b) for b in self.boundaries],
                "points": {k: list(v) for k, v in self.points.items()},
                "stages": [stage_to_dict(s) for s in self.stages], "solver": self.solver,
                "after_failure": self.after_failure}
        if self.continuum is not None:       # absent when None: older files hash the same
            out["continuum"] = self.continuum
        return out

    @classmethod
    def from_dict(cls, d: dict) -> "Scene":
        """A scene from its file form. Every level is checked before anything is built: an
        unknown key (with a "did you mean" and the allowed keys), a missing one, a value of
        the wrong kind (``regions.check_fields``), each naming where it is. A "$schema" key
        (an editor's link to ``dem_core/scene.schema.json``) is ignored. Then the physics
        (``plausibility``): a water table below the whole model is refused, and each unusual
        value (a reservoir, a density, friction or cohesion that looks like a unit slip) is a
        ``ScenePlausibilityWarning``."""
        if isinstance(d, dict) and "$schema" in d:
            d = {k: v for k, v in d.items() if k != "$schema"}
        check_keys(d, _SCENE_KEYS, "scene", required=("geometry", "materials", "density"))
        for key, kind in _SCENE_KINDS.items():
            if key in d and not isinstance(d[key], kind) and not (
                    key == "continuum" and d[key] is None):
                raise ValueError(f"scene: {key} must be a "
                                 f"{_KIND_WORDS[kind]}, got {d[key]!r}"[:300])
        mats = {}
        for k, m in d["materials"].items():
            check_fields(m, Material, f"materials[{k!r}]")
            mats[k] = Material(**m).validated(f"materials[{k!r}]")
        try:
            geometry = GeometrySpec.from_dict(d["geometry"], "geometry")
        except TypeError as e:                   # anything the checks above did not name
            raise ValueError(f"scene geometry: {e}") from None
        scene = cls(geometry=geometry, materials=mats, density=d["density"],
                    block_E=d.get("block_E"), block_nu=d.get("block_nu", 0.25),
                    groups=d.get("groups", {}),
                    boundaries=[_boundary(b, i) for i, b in enumerate(d.get("boundaries", []))],
                    points=d.get("points", {}),
                    stages=[_stage(s, i) for i, s in enumerate(d.get("stages", []))],
                    solver=d.get("solver", {}), name=d.get("name", "scene"),
                    description=d.get("description", ""),
                    after_failure=d.get("after_failure", "stop"),
                    continuum=d.get("continuum"))
        plausibility.check_no_gaps(scene)
        plausibility.check_water_reaches(scene)
        plausibility.warn_unusual(scene)
        return scene

    def save(self, path) -> None:
        """Write the scene as readable JSON."""
        text = json.dumps(self.to_dict(), indent=1)
        # a list of plain numbers on one line: [x, y] pairs stay readable
        text = re.sub(r"\[\s+([-+0-9.eE,\s]+?)\s+\]",
                      lambda m: "[" + " ".join(m.group(1).split()) + "]", text)
        with open(path, "w") as fh:
            fh.write(text + "\n")

    @classmethod
    def load(cls, path) -> "Scene":
        """Read and check a scene file (ValueError naming the bad item; a key given twice in
        one object is refused, naming it and where it is)."""
        with open(path) as fh:
            return cls.from_dict(load_json(fh))


# ---------------------------------------------------------------------- building
def build_model(scene: Scene, blocks=None, **options):
    """The DEM ``Model`` of a scene: blocks (built from the geometry unless given), materials,
    groups resolved into ``blocks.groups``, boundaries applied, monitoring points added.
    ``options`` override the scene's solver options. Blocks under 1e-4 of the median area are
    a ``ScenePlausibilityWarning`` (``plausibility.warn_slivers``)."""
    from ..geometry import build_block_system
    from ..model import Model

    blocks = build_block_system(scene.geometry) if blocks is None else blocks
    plausibility.warn_slivers(blocks)
    blocks.groups.update(resolve_groups(scene, blocks))
    solver = dict(scene.solver, **options)
    model = Model(blocks, scene.materials, density=scene.density, block_E=scene.block_E,
                  block_nu=scene.block_nu, **solver)
    for b in scene.boundaries:
        sides = group_sides(scene, b.group)
        model.fix(b.group, x=b.x, y=b.y, rotation=b.rotation, at=sides)
        # a deformable block is held per gridpoint, so every one on those sides is held there,
        # also one a "minus" took out of the group (a corner block of the base and a roller)
        if sides and model.deformable_blocks.any():
            near = np.unique(np.concatenate([blocks.touching(s) for s in sides]))
            extra = np.setdiff1d(near[model.deformable_blocks[near]], model.group(b.group))
            if extra.size:
                model.fix(extra, x=b.x, y=b.y, rotation=b.rotation, at=sides)
    check_points_in_blocks(scene.points, blocks, model.props.active)
    for name, xy in scene.points.items():
        model.add_history_point(name, xy)
    return model


def check_points_in_blocks(points, blocks, active=None) -> None:
    """ValueError naming the first monitoring point (name -> (x, y) m) that no (active) block
    of ``blocks`` contains: ``Model.add_history_point`` would attach it to the nearest block.
    A point on a block's edge (within 1e-9 of the model's size) is inside."""
    if not points:
        return
    v = np.asarray(blocks.vertices, dtype=np.float64)
    off = np.asarray(blocks.vertex_offsets)
    lo, hi = np.minimum.reduceat(v, off[:-1]), np.maximum.reduceat(v, off[:-1])
    tol = 1e-9 * max(1.0, float(np.hypot(*(v.max(0) - v.min(0)))))
    act = np.ones(len(lo), bool) if active is None else np.asarray(active)[:len(lo)] > 0
    for name, xy in points.items():
        p = np.asarray(xy, dtype=np.float64)
        near = np.flatnonzero(act & np.all(lo - tol <= p, axis=1) & np.all(p <= hi + tol, axis=1))
        if not any(shapely.distance(shapely.Polygon(v[off[b]:off[b + 1]]), shapely.Point(p))
                   <= tol for b in near):
            raise ValueError(f"monitoring point {name!r} at ({p[0]:g}, {p[1]:g}) m is in no "
                             f"block of the model (blocks span x {v[:, 0].min():g}.."
                             f"{v[:, 0].max():g}, y {v[:, 1].min():g}..{v[:, 1].max():g} m)")


def conventional(scene: Scene, zone_size: float, plastic: bool = False) -> Scene:
    """The thesis's conventional model of a scene (thesis 4.2.2: UDEC with the joints only):
    the same regions, joints, materials, groups, boundaries, points and
    stages, without the Voronoi flaws (each region is the blocks its joints cut it into), every
    block deformable with zones of ``zone_size`` m (the scene's ``block_E`` and ``block_nu``;
    docs/mechanics.md, "The conventional model"). ``plastic``: each region's zones are
    Mohr-Coulomb with its flaws' strength (the material "flaw:<region>": cohesion, friction,
    tensile strength; no dilation), the intact rock the damage model's flaws stand for;
    else elastic. The solver options deformable blocks do not take yet (``rounding``,
    ``edge_elements``, the eigen ``step_estimate``) are dropped."""
    if scene.block_E is None:
        raise ValueError(f"conventional: scene {scene.name!r} has rigid blocks (block_E None); "
                         "its conventional model needs their modulus")
    _positive("conventional zone size (m)", zone_size)
    solver = {k: v for k, v in scene.solver.items()
              if k not in ("rounding", "edge_elements", "step_estimate")}
    solver["deformable"] = {"*": float(zone_size)}
    if plastic:
        solver["zone_strength"] = {}
        for r in scene.geometry.regions:
            f = material_for(f"flaw:{r.name}", scene.materials)
            solver["zone_strength"][r.name] = dict(cohesion=f.cohesion, friction=f.friction,
                                                   tensile_strength=f.tensile_strength)
    return dataclasses.replace(scene, geometry=dataclasses.replace(scene.geometry, voronoi={}),
                               solver=solver, name=f"{scene.name} conventional")


def group_sides(scene: Scene, name):
    """The sides of the model's box a group is defined by (a list of "left", "right", "bottom",
    "top"), or None when it is not (a region, a polygon, or a group the scene does not define):
    where a held deformable block is held (``Model.set_velocity``)."""
    sel = scene.groups.get(name)
    if sel is None:
        return None
    (kind, arg), = sel.items()
    if kind == "touching":
        return [arg]
    if kind in ("union", "minus"):
        parts = [group_sides(scene, n) for n in (arg if kind == "union" else arg[:1])]
        if any(p is None for p in parts):
            return None
        return sorted({s for p in parts for s in p})
    return None


def resolve_groups(scene: Scene, blocks) -> dict:
    """name -> (m,) int64 block indices of every scene group (in definition order, so a group
    may use the ones before it)."""
    out = {}

    def named(n):
        return out[n] if n in out else np.asarray(blocks.groups[n], dtype=np.int64)

    for name, sel in scene.groups.items():
        (kind, arg), = sel.items()
        if kind == "touching":
            idx = blocks.touching(arg)
        elif kind == "region":
            idx = named(arg)
        elif kind == "inside":
            poly = shapely.Polygon(arg)
            idx = np.flatnonzero(shapely.contains_xy(poly, blocks.centroid[:, 0],
                                                     blocks.centroid[:, 1]))
        elif kind == "union":
            idx = np.unique(np.concatenate([named(n) for n in arg]))
        else:                                         # "minus"
            idx = np.setdiff1d(named(arg[0]), named(arg[1]))
        out[name] = np.asarray(idx, dtype=np.int64)
    return out


def contact_material_names(geometry: GeometrySpec) -> list:
    """The contact materials a geometry's blocks will have: "flaw:<region>", "joint:<name>",
    "boundary:<A>|<B>" for regions sharing a boundary (as ``geometry.build`` names them)."""
    names = [f"flaw:{r.name}" for r in geometry.regions]
    names += [f"joint:{j.name}" for j in geometry.joint_sets + geometry.joints]
    polys = [r.polygon() for r in geometry.regions]
    for i in range(len(polys)):
        for j in range(i + 1, len(polys)):
            if polys[i].boundary.intersection(polys[j].boundary).length > 0.0:
                names.append(f"boundary:{geometry.regions[i].name}|{geometry.regions[j].name}")
    return names


def check_continuum(section, regions) -> None:
    """Check a scene's "continuum" section (``CONTINUUM_KEYS``): ``h`` a mesh size > 0 (m),
    ``materials`` {region name or fnmatch pattern: {"kind": one of ``CONTINUUM_MATERIALS``,
    its fields}} covering every region of ``regions`` (names), each key matching one,
    ``flow`` one of ``CONTINUUM_FLOWS`` and ``search_step`` {"g": > 0, "F": > 0}. ValueError naming the bad key; the values' ranges
    are checked when the materials are built (``continuum_ref.scene_run``)."""
    import fnmatch

    check_keys(section, CONTINUUM_KEYS, "continuum", required=("h", "materials"))
    _positive("continuum: h (mesh size, m)", section["h"])
    if section.get("flow", "native") not in CONTINUUM_FLOWS:
        raise ValueError(f"continuum: flow must be one of {CONTINUUM_FLOWS}, got "
                         f"{section['flow']!r}")
    if section.get("refine") is not None:
        _check_refine(section["refine"], float(section["h"]))
    if section.get("search_step") is not None:
        step = section["search_step"]
        if not isinstance(step, dict):
            raise ValueError(f"continuum: search_step must be a mapping with keys among "
                             f"{SEARCH_STEP_KEYS}, got {step!r}"[:300])
        check_keys(step, SEARCH_STEP_KEYS, "continuum: search_step")
        for k, v in step.items():
            _positive(f"continuum: search_step {k}", v)
    mats = section["materials"]
    if not isinstance(mats, dict) or not mats:
        raise ValueError(f"continuum: materials must be a mapping region (or pattern) -> "
                         f"material, got {mats!r}"[:300])
    for key, m in mats.items():
        where = f"continuum: materials[{key!r}]"
        if not any(fnmatch.fnmatchcase(r, key) for r in regions):
            raise ValueError(f"{where} matches no region; regions are {sorted(regions)}")
        if not isinstance(m, dict) or m.get("kind") not in CONTINUUM_MATERIALS:
            got = m.get("kind") if isinstance(m, dict) else m
            raise ValueError(f"{where}: kind must be one of {list(CONTINUUM_MATERIALS)}, got "
                             f"{got!r}"[:300])
        takes, needs = CONTINUUM_MATERIALS[m["kind"]]
        check_keys(m, ("kind",) + takes, f"{where} ({m['kind']})", required=needs)
        for k, v in m.items():
            if k == "bound":
                if v not in DEM_ROCK_MASS_BOUNDS:
                    raise ValueError(f"{where}: bound must be one of {DEM_ROCK_MASS_BOUNDS}, "
                                     f"got {v!r}")
            elif k != "kind" and not (v is None or (_number(v) and math.isfinite(v))):
                raise ValueError(f"{where}: {k} must be a number, got {v!r}")
        if m["kind"] == "hoek_brown" and not ({"gsi", "mi"} <= set(m)
                                              or {"mb", "s", "a", "E"} <= set(m)):
            raise ValueError(f"{where} (hoek_brown): give gsi and mi (and D), or mb, s, a "
                             f"and E")
    for r in regions:
        if not any(fnmatch.fnmatchcase(r, key) for key in mats):
            raise ValueError(f"continuum: region {r!r} has no material (materials: "
                             f"{sorted(mats)})")


def _check_refine(refine, h) -> None:
    """The continuum's graded mesh (``REFINE_KEYS``): points a non-empty list of [x, y] (m),
    h_far >= h, 0 <= d_near < d_far (m)."""
    where = "continuum: refine"
    if not isinstance(refine, dict):
        raise ValueError(f"{where} must be a mapping with {REFINE_KEYS}, got {refine!r}"[:300])
    check_keys(refine, REFINE_KEYS, where, required=REFINE_KEYS)
    pts = refine["points"]
    if not (isinstance(pts, list) and pts and all(
            isinstance(q, (list, tuple)) and len(q) == 2
            and all(_number(v) and math.isfinite(v) for v in q) for q in pts)):
        raise ValueError(f"{where}: points must be a list of [x, y] (m), got {pts!r}"[:300])
    for k in ("h_far", "d_near", "d_far"):
        if not (_number(refine[k]) and math.isfinite(refine[k])):
            raise ValueError(f"{where}: {k} must be a number, got {refine[k]!r}")
    if not refine["h_far"] >= h:
        raise ValueError(f"{where}: h_far {refine['h_far']!r} must be at least h = {h} m")
    if not 0.0 <= refine["d_near"] < refine["d_far"]:
        raise ValueError(f"{where}: needs 0 <= d_near < d_far (m), got d_near "
                         f"{refine['d_near']!r}, d_far {refine['d_far']!r}")


# ---------------------------------------------------------------------- helpers
def _positive(what, v):
    if not (_number(v) and math.isfinite(v) and v > 0):
        raise ValueError(f"{what} must be finite and > 0, got {v!r}")


_KIND_WORDS = {str: "string", dict: "mapping (a JSON object {...})",
               list: "list (a JSON array [...])"}
_KIND_OF = {cls: kind for kind, cls in STAGE_KINDS.items()}
_UNSAFE_NAME = re.compile(r"[/\\\x00-\x1f]")


def _number(v) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_))


def check_name(name) -> None:
    """A scene's name is a plain file-name stem: its results go to ``<out>/<name>``, so "..",
    "." or a name with a path separator would write outside that folder (ValueError)."""
    if not (isinstance(name, str) and name.strip() and not _UNSAFE_NAME.search(name)
            and name.strip(". ")):
        raise ValueError(f"scene name must be a plain file name (no '/', '\\', control "
                         f"characters, not only dots), got {name!r}")


def load_json(fh):
    """``json.load`` of a scene file refusing a key given twice in one object (JSON keeps the
    last in silence): ValueError naming the key and where it is."""
    twice, keep = {}, []

    def pairs(items):
        out = {}
        for k, v in items:
            if k in out and id(out) not in twice:
                twice[id(out)] = k
            out[k] = v
        keep.append(out)                 # the ids stay those objects' until the walk below
        return out

    data = json.load(fh, object_pairs_hook=pairs)
    if twice:
        where = _path_of(data, twice, "")
        at, key = where if where is not None else ("", "?")
        raise ValueError(f"duplicate key {key!r} " + (f"in {at}" if at else "at the top level")
                         + " (JSON would keep only the last; give each key once)")
    return data


def _path_of(node, twice, path):
    """(path, key) of the first object of ``node`` in ``twice`` (id -> duplicate key)."""
    if isinstance(node, dict):
        if id(node) in twice:
            return path, twice[id(node)]
        for k, v in node.items():
            sub = f"{path}.{k}" if re.fullmatch(r"[A-Za-z_]\w*", str(k)) else f"{path}[{k!r}]"
            found = _path_of(v, twice, sub.lstrip("."))
            if found is not None:
                return found
    elif isinstance(node, list):
        for i, v in enumerate(node):
            found = _path_of(v, twice, f"{path}[{i}]")
            if found is not None:
                return found
    return None


def _point(name, xy) -> tuple:
    """A monitoring point (x, y) m, or ValueError naming it."""
    if not (isinstance(xy, (list, tuple, np.ndarray)) and len(xy) == 2
            and all(_number(v) for v in xy)):
        raise ValueError(f"points[{name!r}] must be [x, y] in m (two numbers), got {xy!r}")
    return float(xy[0]), float(xy[1])


def _points_in_regions(scene) -> None:
    """A monitoring point outside every region (or in a hole) is refused before any block is
    built: it would be attached to the nearest block (``check_points_in_blocks`` checks the
    blocks themselves in ``build_model``)."""
    if not scene.points:
        return
    rock = shapely.union_all([r.polygon() for r in scene.geometry.regions])
    x0, y0, x1, y1 = rock.bounds
    tol = 1e-9 * max(1.0, math.hypot(x1 - x0, y1 - y0))
    for name, (x, y) in scene.points.items():
        if shapely.distance(rock, shapely.Point(x, y)) > tol:
            raise ValueError(f"monitoring point {name!r} at ({x:g}, {y:g}) m is in no region "
                             f"of the model (its regions span x {x0:g}..{x1:g}, "
                             f"y {y0:g}..{y1:g} m)")


def _boundary(d, i=0) -> Boundary:
    """A boundary from its file form (ValueError naming an unknown key, or a value that is
    not true/false where one is meant)."""
    where = f"boundaries[{i}]"
    if isinstance(d, dict) and isinstance(d.get("group"), str):
        where += f" (group {d['group']!r})"
    return Boundary(**check_fields(d, Boundary, where))


def _check_boundary(b, i) -> None:
    check_fields(dataclasses.asdict(b), Boundary, f"boundaries[{i}]")


def _stage(d, i):
    """A stage from its file form: an unknown kind or key with a "did you mean", a value of
    the wrong kind (``"settle": "no"``, ``"max_steps": true``), each naming the stage."""
    if not isinstance(d, dict):
        raise ValueError(f"stage {i} must be a mapping with a 'kind', got {d!r}"[:300])
    kind = d.get("kind")
    if kind not in STAGE_KINDS:
        close = difflib.get_close_matches(str(kind), list(STAGE_KINDS), n=1)
        raise ValueError(f"stage {i}: unknown kind {kind!r}"
                         + (f" (did you mean {close[0]!r}?)" if close else "")
                         + f"; kinds are {', '.join(sorted(STAGE_KINDS))}")
    cls = STAGE_KINDS[kind]
    check_fields(d, cls, f"stage {i} ({kind})", extra=("kind",))
    if kind == "change_material":
        check_fields(d.get("changes", {}), Material, f"stage {i} (change_material) changes",
                     partial=True)
    return stage_from_dict(d, i)


def _check_selector(name, sel, known):
    if not (isinstance(sel, dict) and len(sel) == 1):
        raise ValueError(f"group {name!r}: a selector is one of {list(GROUP_SELECTORS)} with its "
                         f"argument, e.g. {{\"touching\": \"bottom\"}}, got {sel!r}")
    check_keys(sel, GROUP_SELECTORS, f"groups[{name!r}]")
    (kind, arg), = sel.items()
    if kind == "touching" and arg not in SIDES:
        raise ValueError(f"group {name!r}: touching must name a side {list(SIDES)}, got {arg!r}")
    if kind in ("union", "minus") and not isinstance(arg, list):
        raise ValueError(f"group {name!r}: {kind} takes a list of group names, got {arg!r}")
    refs = [arg] if kind == "region" else (list(arg) if kind in ("union", "minus") else [])
    if kind == "minus" and len(refs) != 2:
        raise ValueError(f"group {name!r}: minus takes two group names, got {arg!r}")
    for r in refs:
        if not isinstance(r, str):
            raise ValueError(f"group {name!r}: {kind} takes group names, got {r!r} (a selector "
                             "inside a selector: define it as a group of its own and name it)")
        if r not in known or r == name:
            raise ValueError(f"group {name!r} refers to unknown group {r!r}")
    if kind == "inside":
        try:
            ok = shapely.Polygon(arg).is_valid and shapely.Polygon(arg).area > 0
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ValueError(f"group {name!r}: 'inside' needs a valid polygon, got {arg!r}")

