"""Regions: named polygons (concave allowed, with holes) that make up a scene.

Coordinates are metres, (x, y) with y up. Orientation of the input rings does not matter.
``check_keys`` and ``check_fields`` are the checks of a scene file's records at every level
(a geometry's, a region's, a joint set's, a material's, a stage's...): unknown keys with a
"did you mean", missing ones, and values of the wrong kind (a string where a bool is meant).
"""
from __future__ import annotations

import dataclasses
import difflib
import numbers
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import Polygon
from shapely.validation import explain_validity


def check_keys(d, allowed, where: str, required=()) -> dict:
    """``d`` itself, after checking that it is a mapping whose keys are all in ``allowed``
    and include every ``required`` one: else a one-line ValueError naming ``where``, the bad
    key, the closest allowed key ("did you mean", ``difflib.get_close_matches``) and the
    allowed keys."""
    if not isinstance(d, dict):
        raise ValueError(f"{where} must be a mapping (a JSON object {{...}}), got "
                         f"{type(d).__name__} {d!r}"[:300])
    allowed = sorted(str(k) for k in allowed)
    unknown = [k for k in d if k not in allowed]
    if unknown:
        parts = []
        for k in unknown:
            close = difflib.get_close_matches(str(k), allowed, n=1, cutoff=0.6)
            parts.append(f"{k!r}" + (f" (did you mean {close[0]!r}?)" if close else ""))
        raise ValueError(f"{where}: unknown key{'s' if len(unknown) > 1 else ''} "
                         f"{', '.join(parts)}; allowed keys: {', '.join(allowed)}")
    missing = [k for k in required if k not in d]
    if missing:
        raise ValueError(f"{where}: missing {', '.join(map(repr, missing))} (required "
                         f"key{'s' if len(missing) > 1 else ''})")
    return d


def _type_name(t) -> str:
    return t if isinstance(t, str) else getattr(t, "__name__", str(t))


def _kind_ok(value, kind: str) -> bool:
    if kind == "bool":
        return isinstance(value, (bool, np.bool_))
    if isinstance(value, (bool, np.bool_)):
        return False                     # true/false where a number or a name is meant
    if kind == "int":
        return isinstance(value, numbers.Integral) or (
            isinstance(value, float) and value.is_integer())
    if kind == "float":
        return isinstance(value, numbers.Real)
    if kind == "str":
        return isinstance(value, str)
    return True


_SAY = {"bool": "true or false", "int": "a whole number", "float": "a number",
        "str": "a string"}


def check_fields(d, cls, where: str, extra=(), skip=(), partial=False) -> dict:
    """``check_keys`` of ``d`` against the fields of dataclass ``cls`` (and the ``extra``
    keys), the fields without a default required, then each value against its field's
    annotation: a bool field takes only true/false, an int field a whole number (not
    true/false), a float field a number, a str field a string (None where the annotation
    allows it). ``skip``: fields not checked here; ``partial``: no field is required (a
    record of changes). ValueError naming ``where``, the key and the value."""
    fields = dataclasses.fields(cls)
    required = [] if partial else [f.name for f in fields if f.default is dataclasses.MISSING
                                   and f.default_factory is dataclasses.MISSING]
    check_keys(d, [f.name for f in fields] + list(extra), where, required)
    for f in fields:
        if f.name not in d or f.name in skip:
            continue
        kinds = [k.strip() for k in _type_name(f.type).split("|")]
        value = d[f.name]
        if value is None and "None" in kinds:
            continue
        scalar = [k for k in kinds if k != "None"]
        if len(scalar) == 1 and scalar[0] in _SAY and not _kind_ok(value, scalar[0]):
            raise ValueError(f"{where}: {f.name} must be {_SAY[scalar[0]]}"
                             f"{' or null' if 'None' in kinds else ''}, got {value!r}")
    return d


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
    def from_dict(cls, d: dict, where: str = "region") -> "Region":
        """A region from its file form (ValueError naming an unknown or missing key)."""
        if isinstance(d, dict) and isinstance(d.get("name"), str):
            where = f"{where} ({d['name']!r})"
        check_fields(d, cls, where)
        for key in ("holes", "groups"):
            if not isinstance(d.get(key, []), list):
                raise ValueError(f"{where}: {key} must be a list, got {d[key]!r}")
        return cls(d["name"], d["exterior"], d.get("holes", []), d.get("groups", []))


def rectangle(name: str, x0: float, y0: float, x1: float, y1: float, groups=()) -> Region:
    """An axis-parallel rectangular region [x0, x1] x [y0, y1]."""
    return Region(name, [(x0, y0), (x1, y0), (x1, y1), (x0, y1)], groups=list(groups))
