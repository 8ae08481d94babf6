"""Regions: named polygons (concave allowed, with holes) that make up a scene.

Coordinates are metres, (x, y) with y up. Orientation of the input rings does not matter.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import Polygon
from shapely.validation import explain_validity


def as_ring(points, what: str) -> np.ndarray:
    """Validate a ring of (x, y) points and return it as an (n, 2) float array without repeat.

    Raises ValueError naming ``what`` for NaN/inf, too few points or duplicate points.
    """
    arr = np.asarray(points, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"{what}: expected a list of (x, y) points, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{what}: coordinates must be finite, got {arr[~np.isfinite(arr).all(1)][:3]}")
    if len(arr) > 1 and np.allclose(arr[0], arr[-1]):
        arr = arr[:-1]
    if len(arr) < 3:
        raise ValueError(f"{what}: a polygon needs at least 3 distinct points, got {len(arr)}")
    return arr


def polygon_from_rings(exterior, holes=(), what: str = "polygon") -> Polygon:
    """A valid shapely polygon (CCW exterior, CW holes) or a ValueError that says why not."""
    ext = as_ring(exterior, f"{what} exterior")
    hls = [as_ring(h, f"{what} hole {i}") for i, h in enumerate(holes)]
    poly = Polygon(ext, hls)
    if not poly.is_valid:
        raise ValueError(f"{what} is not a valid simple polygon: {explain_validity(poly)} "
                         "(self-intersecting ring, hole outside the exterior or touching holes)")
    if poly.area <= 0.0:
        raise ValueError(f"{what} has zero area")
    return shapely.orient_polygons(poly)


@dataclass
class Region:
    """A named area of the scene: polygon ``exterior`` with optional ``holes``.

    Parameters
    ----------
    name : str
        Unique name; also a block group and part of material names ("flaw:<name>").
    exterior : sequence of (x, y), m
        Outer ring, either orientation, concave allowed, first point not repeated (or repeated).
    holes : sequence of rings, m
        Voids (open joints, tunnels). A hole is a free surface unless another region fills it.
    groups : sequence of str
        Extra group names all blocks of this region belong to (e.g. "excavation stage 3").
    """

    name: str
    exterior: list
    holes: list = field(default_factory=list)
    groups: list = field(default_factory=list)

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name or "|" in self.name or ":" in self.name:
            raise ValueError(f"region name must be a non-empty string without '|' or ':', got {self.name!r}")
        self.exterior = as_ring(self.exterior, f"region {self.name!r} exterior").tolist()
        self.holes = [as_ring(h, f"region {self.name!r} hole {i}").tolist()
                      for i, h in enumerate(self.holes)]
        self.groups = [str(g) for g in self.groups]
        self.polygon()  # validates

    def polygon(self) -> Polygon:
        """The region as an oriented, validated shapely polygon."""
        return polygon_from_rings(self.exterior, self.holes, f"region {self.name!r}")

    def to_dict(self) -> dict:
        return {"name": self.name, "exterior": self.exterior, "holes": self.holes,
                "groups": self.groups}

    @classmethod
    def from_dict(cls, d: dict) -> "Region":
        return cls(d["name"], d["exterior"], d.get("holes", []), d.get("groups", []))


def rectangle(name: str, x0: float, y0: float, x1: float, y1: float, groups=()) -> Region:
    """An axis-parallel rectangular region [x0, x1] x [y0, y1]."""
    return Region(name, [(x0, y0), (x1, y0), (x1, y1), (x0, y1)], groups=list(groups))
