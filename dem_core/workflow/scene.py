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
import json
import math
import re
from dataclasses import dataclass, field

import numpy as np
import shapely

from ..geometry import GeometrySpec
from ..settings import SCENE_SOLVER_KEYS
from ..contact.materials import Material, material_for, material_table
from ..deformable.zone_plasticity import new_keys
from .stages import check_stages, stage_from_dict, stage_to_dict

__all__ = ["Scene", "Boundary", "build_model", "conventional", "resolve_groups", "group_sides",
           "GROUP_SELECTORS"]

GROUP_SELECTORS = ("touching", "region", "inside", "union", "minus")
SIDES = ("bottom", "top", "left", "right")
_SCENE_KEYS = {"name", "description", "geometry", "materials", "density", "block_E",
               "block_nu", "groups", "boundaries", "points", "stages", "solver"}
_MATERIAL_KEYS = {f.name for f in dataclasses.fields(Material)}
# Model options a scene may set: the SolverOptions fields but the block moduli (the scene's
# own top-level keys)
SOLVER_KEYS = set(SCENE_SOLVER_KEYS)


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
    (``stages.py``). solver : Model options (``SOLVER_KEYS``).
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

    def __post_init__(self):
        self.boundaries = [b if isinstance(b, Boundary) else Boundary(**b)
                           for b in self.boundaries]
        self.points = {k: (float(v[0]), float(v[1])) for k, v in self.points.items()}
        zs = self.solver.get("zone_strength")
        if isinstance(zs, dict):       # old key names (``zone_plasticity.OLD_KEYS``) renamed
            self.solver = dict(self.solver, zone_strength={
                k: new_keys(row, f"zone_strength[{k!r}]") if isinstance(row, dict) else row
                for k, row in zs.items()})
        self.validate()

    # ------------------------------------------------------------------ checks
    def validate(self) -> None:
        """Raise ValueError naming the bad item; nothing is computed before this passes."""
        _positive("density (kg/m^3)", self.density)
        if self.block_E is not None:
            _positive("block_E (Pa)", self.block_E)
        if not (-1.0 < float(self.block_nu) < 0.5):
            raise ValueError(f"block_nu must be in (-1, 0.5), got {self.block_nu!r}")
        unknown = set(self.solver) - SOLVER_KEYS
        if unknown:
            raise ValueError(f"unknown solver option(s) {sorted(unknown)}; allowed "
                             f"{sorted(SOLVER_KEYS)}")
        for name in contact_material_names(self.geometry):
            material_table([name], self.materials)        # names the missing material
        known = self.group_names()
        earlier = known - set(self.groups)          # a group may use the ones before it
        for gname, sel in self.groups.items():
            _check_selector(gname, sel, earlier)
            earlier.add(gname)
        for b in self.boundaries:
            if b.group not in known:
                raise ValueError(f"boundary on unknown group {b.group!r}; groups are "
                                 f"{sorted(known)}")
        for pname, xy in self.points.items():
            if not all(math.isfinite(v) for v in xy):
                raise ValueError(f"monitoring point {pname!r} is not finite: {xy!r}")
        check_stages(self.stages, known, self.materials)

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
        return {"name": self.name, "description": self.description,
                "geometry": self.geometry.to_dict(),
                "materials": {k: dataclasses.asdict(m) for k, m in self.materials.items()},
                "density": self.density, "block_E": self.block_E, "block_nu": self.block_nu,
                "groups": self.groups,
                "boundaries": [dataclasses.asdict(b) for b in self.boundaries],
                "points": {k: list(v) for k, v in self.points.items()},
                "stages": [stage_to_dict(s) for s in self.stages], "solver": self.solver}

    @classmethod
    def from_dict(cls, d: dict) -> "Scene":
        _no_unknown_keys("scene", d, _SCENE_KEYS)
        for key in ("geometry", "materials", "density"):
            if key not in d:
                raise ValueError(f"scene: missing {key!r}")
        mats = {}
        for k, m in d["materials"].items():
            _no_unknown_keys(f"material {k!r}", m, _MATERIAL_KEYS)
            mats[k] = Material(**m).validated(k)
        try:
            geometry = GeometrySpec.from_dict(d["geometry"])
        except TypeError as e:                   # an unknown field of a joint set, Voronoi...
            raise ValueError(f"scene geometry: {e}") from None
        return cls(geometry=geometry, materials=mats, density=d["density"],
                   block_E=d.get("block_E"), block_nu=d.get("block_nu", 0.25),
                   groups=d.get("groups", {}),
                   boundaries=[_boundary(b) for b in d.get("boundaries", [])],
                   points=d.get("points", {}),
                   stages=[stage_from_dict(s, i) for i, s in enumerate(d.get("stages", []))],
                   solver=d.get("solver", {}), name=d.get("name", "scene"),
                   description=d.get("description", ""))

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
        """Read and check a scene file (ValueError naming the bad item)."""
        with open(path) as fh:
            return cls.from_dict(json.load(fh))


# ---------------------------------------------------------------------- building
def build_model(scene: Scene, blocks=None, **options):
    """The DEM ``Model`` of a scene: blocks (built from the geometry unless given), materials,
    groups resolved into ``blocks.groups``, boundaries applied, monitoring points added.
    ``options`` override the scene's solver options."""
    from ..geometry import build_block_system
    from ..model import Model

    blocks = build_block_system(scene.geometry) if blocks is None else blocks
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
    for name, xy in scene.points.items():
        model.add_history_point(name, xy)
    return model


def conventional(scene: Scene, zone_size: float, plastic: bool = False) -> Scene:
    """The thesis's conventional model of a scene (thesis 4.2.2: UDEC with the joints only):
    the same regions, joints, materials, groups, boundaries, points and
    stages, without the Voronoi flaws (each region is the blocks its joints cut it into), every
    block deformable with zones of ``zone_size`` m (the scene's ``block_E`` and ``block_nu``;
    docs/mechanics.md, "The conventional model"). ``plastic``: each region's zones are
    Mohr-Coulomb with its flaws' strength (the material "flaw:<region>": cohesion, friction,
    tensile strength; no dilation), the intact rock the damage model's flaws stand for;
    else elastic. The solver options deformable blocks do not take yet (``rounding``,
    ``edge_elements``) are dropped."""
    if scene.block_E is None:
        raise ValueError(f"conventional: scene {scene.name!r} has rigid blocks (block_E None); "
                         "its conventional model needs their modulus")
    _positive("conventional zone size (m)", zone_size)
    solver = {k: v for k, v in scene.solver.items() if k not in ("rounding", "edge_elements")}
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


# ---------------------------------------------------------------------- helpers
def _positive(what, v):
    if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
        raise ValueError(f"{what} must be finite and > 0, got {v!r}")


def _no_unknown_keys(what, d, allowed):
    if not isinstance(d, dict):
        raise ValueError(f"{what} must be a mapping, got {type(d).__name__}")
    unknown = set(d) - set(allowed)
    if unknown:
        raise ValueError(f"{what}: unknown key(s) {sorted(unknown)}; allowed {sorted(allowed)}")


def _boundary(d) -> Boundary:
    _no_unknown_keys("boundary", d, {f.name for f in dataclasses.fields(Boundary)})
    return Boundary(**d)


def _check_selector(name, sel, known):
    if not (isinstance(sel, dict) and len(sel) == 1 and next(iter(sel)) in GROUP_SELECTORS):
        raise ValueError(f"group {name!r}: a selector is one of {list(GROUP_SELECTORS)} with its "
                         f"argument, got {sel!r}")
    (kind, arg), = sel.items()
    if kind == "touching" and arg not in SIDES:
        raise ValueError(f"group {name!r}: touching must name a side {list(SIDES)}, got {arg!r}")
    refs = [arg] if kind == "region" else (list(arg) if kind in ("union", "minus") else [])
    if kind == "minus" and len(refs) != 2:
        raise ValueError(f"group {name!r}: minus takes two group names, got {arg!r}")
    for r in refs:
        if r not in known or r == name:
            raise ValueError(f"group {name!r} refers to unknown group {r!r}")
    if kind == "inside":
        try:
            ok = shapely.Polygon(arg).is_valid and shapely.Polygon(arg).area > 0
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ValueError(f"group {name!r}: 'inside' needs a valid polygon, got {arg!r}")

