"""The scene geometry as plain data: regions, joints, Voronoi specs and groups.

``GeometrySpec`` is what both methods read: ``dem_core`` builds blocks from it and
``continuum_ref`` meshes the same regions. ``to_dict``/``from_dict`` round-trip through JSON.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely

from .joints import JointLine, JointSet
from .regions import Region, check_fields, check_keys, polygon_from_rings

GEOMETRY_KEYS = ("regions", "joint_sets", "joints", "voronoi", "groups")


@dataclass
class ZoneSizeField:
    """A size field h(x, y): ``inside`` in a zone polygon, growing linearly to ``outside``.

    h = inside for points in ``zone``; h = inside + (outside - inside) * min(d / transition, 1)
    at distance d (m) from it. Plain data, so it survives ``GeometrySpec.to_dict``.
    """

    zone: list
    inside: float
    outside: float
    transition: float

    def __post_init__(self):
        polygon_from_rings(self.zone, (), "size field zone")
        for nm in ("inside", "outside", "transition"):
            v = float(getattr(self, nm))
            if not (np.isfinite(v) and v > 0):
                raise ValueError(f"ZoneSizeField.{nm} must be finite and > 0, got {v}")
        self._poly = polygon_from_rings(self.zone, (), "size field zone")
        shapely.prepare(self._poly)

    def __call__(self, x, y):
        d = shapely.distance(self._poly, shapely.points(np.asarray(x, float), np.asarray(y, float)))
        return self.inside + (self.outside - self.inside) * np.minimum(d / self.transition, 1.0)

    def to_dict(self) -> dict:
        return {"kind": "ZoneSizeField", "zone": [list(map(float, p)) for p in self.zone],
                "inside": self.inside, "outside": self.outside, "transition": self.transition}


@dataclass
class Voronoi:
    """How to tessellate a region into Voronoi blocks (the flaws are their shared edges).

    Parameters
    ----------
    edge_length : float
        Target mean block edge length, m (UDEC's "edge length").
    relax_iterations : int
        Lloyd relaxation steps of the interior seeds (thesis: up to 100; more = more uniform).
    seed : int
        Random seed of the interior seed points. Same seed, same blocks.
    size_field : callable h(x, y) -> array, optional
        Local target edge length (m) from arrays of x and y; overrides ``edge_length`` locally
        (``edge_length`` is then only used for input checks). Use ``ZoneSizeField`` to keep the
        spec savable as JSON.
    edge_seeding : bool
        Place fixed seed rows along region edges and mirrored seed pairs along joint segments so
        block edges follow boundaries and joints (UDEC places points along each edge).
    min_edge_fraction : float
        Sliver control: edges shorter than this fraction of the local edge length are removed by
        merging their end vertices (the region stays exactly covered).
    min_area_fraction : float
        Sliver control: blocks smaller than this fraction of h^2 (h the local edge length; a
        regular hexagon of edge h has area 2.6 h^2) are merged into a neighbour across a flaw
        when the union is convex.
    """

    edge_length: float
    relax_iterations: int = 20
    seed: int = 0
    size_field: object = None
    edge_seeding: bool = True
    min_edge_fraction: float = 0.15
    min_area_fraction: float = 0.15

    def __post_init__(self):
        if not (np.isfinite(self.edge_length) and self.edge_length > 0):
            raise ValueError(f"Voronoi edge_length must be finite and > 0, got {self.edge_length}")
        if int(self.relax_iterations) != self.relax_iterations or self.relax_iterations < 0:
            raise ValueError(f"relax_iterations must be an integer >= 0, got {self.relax_iterations}")
        if not 0.0 <= self.min_edge_fraction < 0.5:
            raise ValueError(f"min_edge_fraction must be in [0, 0.5), got {self.min_edge_fraction}")
        if not 0.0 <= self.min_area_fraction < 1.0:
            raise ValueError(f"min_area_fraction must be in [0, 1), got {self.min_area_fraction}")
        if self.size_field is not None and not callable(self.size_field):
            raise ValueError("size_field must be callable h(x, y) or None")
        self.relax_iterations = int(self.relax_iterations)

    def local_size(self, xy: np.ndarray) -> np.ndarray:
        """Target edge length (m) at points ``xy`` (n, 2); checked positive and finite."""
        xy = np.asarray(xy, float).reshape(-1, 2)
        if self.size_field is None:
            return np.full(len(xy), float(self.edge_length))
        h = np.asarray(self.size_field(xy[:, 0], xy[:, 1]), float) * np.ones(len(xy))
        if not np.all(np.isfinite(h) & (h > 0)):
            raise ValueError(f"size_field returned non-positive or non-finite sizes, e.g. {h[~(h > 0)][:3]}")
        return h

    def to_dict(self) -> dict:
        sf = self.size_field
        if sf is not None and not hasattr(sf, "to_dict"):
            raise TypeError("this Voronoi size_field is a plain callable and cannot be saved; "
                            "use ZoneSizeField (or an object with to_dict) instead")
        return {"edge_length": self.edge_length, "relax_iterations": self.relax_iterations,
                "seed": self.seed, "size_field": None if sf is None else sf.to_dict(),
                "edge_seeding": self.edge_seeding, "min_edge_fraction": self.min_edge_fraction,
                "min_area_fraction": self.min_area_fraction}

    @classmethod
    def from_dict(cls, d: dict, where: str = "voronoi") -> "Voronoi":
        """A Voronoi spec from its file form (ValueError naming ``where`` and an unknown or
        missing key, or a value of the wrong kind)."""
        d = dict(check_fields(d, cls, where, skip=("size_field",)))
        sf = d.pop("size_field", None)
        if sf is not None:
            sf = dict(check_fields(sf, ZoneSizeField, f"{where}.size_field", extra=("kind",)))
            if sf.pop("kind", "ZoneSizeField") != "ZoneSizeField":
                raise ValueError(f"{where}.size_field: unknown kind in {sf}; the one kind is "
                                 "'ZoneSizeField'")
            sf = ZoneSizeField(**sf)
        return cls(size_field=sf, **d)


@dataclass
class GeometrySpec:
    """A scene's geometry: regions, joints, which regions get Voronoi flaws, named groups.

    Parameters
    ----------
    regions : list of Region
        Non-overlapping regions (they may share edges).
    joint_sets : list of JointSet
    joints : list of JointLine
    voronoi : dict region name -> Voronoi
        Regions to tessellate; the others stay as the blocks the joints cut them into.
    groups : dict name -> polygon (list of (x, y))
        Extra block groups: the blocks whose centroid lies in the polygon.
    """

    regions: list
    joint_sets: list = field(default_factory=list)
    joints: list = field(default_factory=list)
    voronoi: dict = field(default_factory=dict)
    groups: dict = field(default_factory=dict)

    def __post_init__(self):
        self.regions, self.joint_sets, self.joints = (list(self.regions), list(self.joint_sets),
                                                      list(self.joints))
        self.voronoi, self.groups = dict(self.voronoi), dict(self.groups)
        self.validate()

    def validate(self) -> None:
        """Raise ValueError naming the problem; called on construction and before building."""
        if not self.regions:
            raise ValueError("GeometrySpec needs at least one region")
        names = [r.name for r in self.regions]
        if len(set(names)) != len(names):
            raise ValueError(f"region names must be unique, got {names}")
        polys = [r.polygon() for r in self.regions]
        tree = shapely.STRtree(polys)
        for i, j in tree.query(polys, predicate="intersects").T:
            if i < j:
                ov = polys[i].intersection(polys[j]).area
                if ov > 1e-9 * min(polys[i].area, polys[j].area):
                    raise ValueError(f"regions {names[i]!r} and {names[j]!r} overlap (area {ov:.3g} m2)")
        jn = [j.name for j in self.joint_sets] + [j.name for j in self.joints]
        if len(set(jn)) != len(jn):
            raise ValueError(f"joint set/line names must be unique, got {jn}")
        for j in self.joint_sets + self.joints:
            for rn in (j.regions or []):
                if rn not in names:
                    raise ValueError(f"joint {j.name!r} refers to unknown region {rn!r}")
        for rn, vs in self.voronoi.items():
            if rn not in names:
                raise ValueError(f"voronoi spec for unknown region {rn!r} (regions: {names})")
            if not isinstance(vs, Voronoi):
                raise ValueError(f"voronoi[{rn!r}] must be a Voronoi, got {type(vs).__name__}")
            area = polys[names.index(rn)].area
            if vs.edge_length > np.sqrt(area):
                raise ValueError(f"Voronoi edge_length {vs.edge_length} m is larger than region "
                                 f"{rn!r} (sqrt of its area = {np.sqrt(area):.4g} m)")
        for gn, gp in self.groups.items():
            polygon_from_rings(gp, (), f"group {gn!r}")
            if gn in names:
                raise ValueError(f"group {gn!r} has the name of a region")

    def to_dict(self) -> dict:
        return {"regions": [r.to_dict() for r in self.regions],
                "joint_sets": [j.to_dict() for j in self.joint_sets],
                "joints": [j.to_dict() for j in self.joints],
                "voronoi": {k: v.to_dict() for k, v in self.voronoi.items()},
                "groups": {k: [list(map(float, p)) for p in v] for k, v in self.groups.items()}}

    @classmethod
    def from_dict(cls, d: dict, where: str = "geometry") -> "GeometrySpec":
        """A geometry from its file form. Every level is checked (``regions.check_fields``):
        an unknown key (a typo: "joint_set", "dip") is refused naming where it is, with a
        "did you mean" and the allowed keys, as is a missing key or a value of the wrong
        kind."""
        check_keys(d, GEOMETRY_KEYS, where, required=("regions",))
        for key, kind in (("regions", list), ("joint_sets", list), ("joints", list),
                          ("voronoi", dict), ("groups", dict)):
            if key in d and not isinstance(d[key], kind):
                raise ValueError(f"{where}.{key} must be a "
                                 f"{'list' if kind is list else 'mapping'}, got {d[key]!r}"[:300])

        def _joint(x, i, jcls, key):
            w = f"{where}.{key}[{i}]"
            if isinstance(x, dict) and isinstance(x.get("name"), str):
                w += f" ({x['name']!r})"
            x = dict(check_fields(x, jcls, w, extra=("kind",)))
            kind = x.pop("kind", jcls.__name__)
            if kind != jcls.__name__:
                raise ValueError(f"{w}: kind {kind!r} in {key}; it takes {jcls.__name__!r}")
            return jcls(**x)

        return cls(regions=[Region.from_dict(r, f"{where}.regions[{i}]")
                            for i, r in enumerate(d["regions"])],
                   joint_sets=[_joint(j, i, JointSet, "joint_sets")
                               for i, j in enumerate(d.get("joint_sets", []))],
                   joints=[_joint(j, i, JointLine, "joints")
                           for i, j in enumerate(d.get("joints", []))],
                   voronoi={k: Voronoi.from_dict(v, f"{where}.voronoi[{k!r}]")
                            for k, v in d.get("voronoi", {}).items()},
                   groups=dict(d.get("groups", {})))
