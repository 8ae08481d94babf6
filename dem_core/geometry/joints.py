"""Joint sets and explicit joint lines, and their traces inside the regions.

Conventions
-----------
- ``dip_deg`` is the apparent dip in the section, degrees from horizontal, 0 <= dip <= 90.
- ``dip_direction`` says which way the joint goes down: ``"right"`` (towards +x) or ``"left"``
  (towards -x). The slope builders of this toolkit put the slope face going down to the right
  (+x), so joints "dipping into the slope" have ``dip_direction="left"`` and joints dipping out
  of the slope (with the face) have ``dip_direction="right"``.
- ``spacing`` is measured normal to the joints (m). Joint ``i`` (any integer) is the line at
  signed normal distance ``offset + i * spacing`` (+ jitter) from ``origin``.
- Persistence ``k`` = joint length / total trace length. A non-persistent set (k < 1) repeats
  ``trace_length`` of joint and ``bridge_length`` of intact rock along each line, with
  ``k = trace / (trace + bridge)``; give k and one of the two lengths. The pattern starts at a
  random phase per line (from ``seed``) unless ``phase`` (m along the line) is given.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import LineString
from shapely.ops import substring

from .regions import as_ring


def _check_name(name, what):
    if not isinstance(name, str) or not name or "|" in name or ":" in name:
        raise ValueError(f"{what} name must be a non-empty string without '|' or ':', got {name!r}")


@dataclass
class JointSet:
    """A set of parallel straight joints (see module docstring for the conventions).

    Parameters
    ----------
    name : str
        Set name; joint contacts get material "joint:<name>".
    dip_deg : float
        Dip from horizontal in degrees, [0, 90].
    spacing : float
        Normal spacing between joints, m, > 0.
    persistence : float
        k in [0, 1]. k = 1: persistent joints that cut regions into columns/beds. k = 0: no joint
        segments (in regions without Voronoi the lines still cut the rock, as flaw edges).
    trace_length, bridge_length : float, optional
        Joint and intact-bridge lengths along a line, m (needed for 0 < k < 1: give one).
    offset : float
        Normal shift of the whole set from ``origin``, m.
    jitter : float
        Random normal shift of each joint, as a fraction of spacing, in [0, 1): uniform in
        ``+-jitter * spacing / 2``.
    seed : int
        Seed for jitter and phases. Same seed, same joints.
    regions : list of str, optional
        Regions the set cuts (default: all).
    dip_direction : {"right", "left"}
        Which way the joints go down (towards +x or -x).
    origin : (x, y)
        A point on joint 0 before offset and jitter, m.
    phase : float, optional
        Distance along each line (from the origin's projection, measured in the down-dip
        direction) where a joint segment starts; default random per line.
    """

    name: str
    dip_deg: float
    spacing: float
    persistence: float = 1.0
    trace_length: float | None = None
    bridge_length: float | None = None
    offset: float = 0.0
    jitter: float = 0.0
    seed: int = 0
    regions: list | None = None
    dip_direction: str = "right"
    origin: tuple = (0.0, 0.0)
    phase: float | None = None

    def __post_init__(self):
        _check_name(self.name, "joint set")
        w = f"joint set {self.name!r}"
        for attr in ("dip_deg", "spacing", "persistence", "offset", "jitter"):
            v = float(getattr(self, attr))
            if not np.isfinite(v):
                raise ValueError(f"{w}: {attr} must be finite, got {v}")
            setattr(self, attr, v)
        if not 0.0 <= self.dip_deg <= 90.0:
            raise ValueError(f"{w}: dip_deg must be in [0, 90], got {self.dip_deg} "
                             "(use dip_direction='left'/'right' for the dip sense)")
        if self.spacing <= 0.0:
            raise ValueError(f"{w}: spacing must be > 0, got {self.spacing}")
        if not 0.0 <= self.persistence <= 1.0:
            raise ValueError(f"{w}: persistence k must be in [0, 1], got {self.persistence}")
        if not 0.0 <= self.jitter < 1.0:
            raise ValueError(f"{w}: jitter must be in [0, 1), got {self.jitter}")
        if self.dip_direction not in ("right", "left"):
            raise ValueError(f"{w}: dip_direction must be 'right' or 'left', got {self.dip_direction!r}")
        self.origin = tuple(float(v) for v in self.origin)
        if len(self.origin) != 2 or not np.all(np.isfinite(self.origin)):
            raise ValueError(f"{w}: origin must be a finite (x, y), got {self.origin}")
        self._resolve_lengths(w)

    def _resolve_lengths(self, w):
        k, t, b = self.persistence, self.trace_length, self.bridge_length
        for nm, v in (("trace_length", t), ("bridge_length", b)):
            if v is not None and not (np.isfinite(v) and v >= 0):
                raise ValueError(f"{w}: {nm} must be finite and >= 0, got {v}")
        if 0.0 < k < 1.0:
            if t is None and b is None:
                raise ValueError(f"{w}: persistence {k} < 1 needs trace_length or bridge_length")
            if t is not None and b is not None:
                if abs(t / (t + b) - k) > 1e-9:
                    raise ValueError(f"{w}: trace_length {t} and bridge_length {b} give k = "
                                     f"{t / (t + b):.6g}, not persistence {k}")
            elif t is None:
                t = b * k / (1.0 - k)
            else:
                b = t * (1.0 - k) / k
            if t <= 0 or b <= 0:
                raise ValueError(f"{w}: trace and bridge lengths must be > 0, got {t}, {b}")
            self.trace_length, self.bridge_length = float(t), float(b)
        if self.phase is not None and not np.isfinite(self.phase):
            raise ValueError(f"{w}: phase must be finite, got {self.phase}")

    # -- geometry -----------------------------------------------------------------------------
    def direction(self) -> np.ndarray:
        """Unit vector along the joints, pointing down-dip."""
        d = np.radians(self.dip_deg)
        sx = 1.0 if self.dip_direction == "right" else -1.0
        return np.array([sx * np.cos(d), -np.sin(d)])

    def normal(self) -> np.ndarray:
        """Unit normal to the joints (the direction spacing is measured in)."""
        u = self.direction()
        return np.array([-u[1], u[0]])

    def lines(self, bounds) -> list:
        """The joint lines crossing the box ``bounds = (xmin, ymin, xmax, ymax)``.

        Returns a list of ``(index, p0, p1, intervals)``: the line through the box from ``p0`` to
        ``p1`` (down-dip) and its joint intervals as (start, end) distances from ``p0``, m.
        """
        u, n, o = self.direction(), self.normal(), np.asarray(self.origin)
        xmin, ymin, xmax, ymax = bounds
        corners = np.array([[xmin, ymin], [xmax, ymin], [xmax, ymax], [xmin, ymax]]) - o
        dn, du = corners @ n, corners @ u
        pad = 1.0 * self.spacing
        i0 = int(np.floor((dn.min() - self.offset - pad) / self.spacing))
        i1 = int(np.ceil((dn.max() - self.offset + pad) / self.spacing))
        t_lo, t_hi = du.min() - 1.0, du.max() + 1.0
        out = []
        for i in range(i0, i1 + 1):
            rng = np.random.default_rng([int(self.seed) & 0x7FFFFFFF, i + 2**31])
            shift = (rng.uniform(-0.5, 0.5) * self.jitter * self.spacing) if self.jitter else 0.0
            c = self.offset + i * self.spacing + shift
            p0, p1 = o + c * n + t_lo * u, o + c * n + t_hi * u
            out.append((i, p0, p1, self._intervals(rng, t_lo, t_hi)))
        return out

    def _intervals(self, rng, t_lo, t_hi) -> np.ndarray:
        length = t_hi - t_lo
        if self.persistence >= 1.0:
            return np.array([[0.0, length]])
        if self.persistence <= 0.0:
            return np.zeros((0, 2))
        period = self.trace_length + self.bridge_length
        phase = rng.uniform(0.0, period) if self.phase is None else float(self.phase)
        m0 = int(np.floor((t_lo - phase) / period)) - 1
        m1 = int(np.ceil((t_hi - phase) / period)) + 1
        starts = phase + np.arange(m0, m1 + 1) * period
        iv = np.column_stack([starts, starts + self.trace_length]) - t_lo
        iv = np.clip(iv, 0.0, length)
        return iv[iv[:, 1] > iv[:, 0]]

    def to_dict(self) -> dict:
        d = dict(self.__dict__)
        d["kind"] = "JointSet"
        d["origin"] = list(self.origin)
        return d


@dataclass
class JointLine:
    """An explicit joint along a polyline ``points`` (m), e.g. a fault or a mapped joint."""

    name: str
    points: list
    regions: list | None = None

    def __post_init__(self):
        _check_name(self.name, "joint line")
        arr = np.asarray(self.points, dtype=float)
        if arr.ndim != 2 or arr.shape[1] != 2 or len(arr) < 2:
            raise ValueError(f"joint line {self.name!r}: need >= 2 (x, y) points, got shape {arr.shape}")
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"joint line {self.name!r}: coordinates must be finite")
        if np.any(np.linalg.norm(np.diff(arr, axis=0), axis=1) == 0.0):
            raise ValueError(f"joint line {self.name!r}: repeated consecutive points")
        if not LineString(arr).is_simple:
            raise ValueError(f"joint line {self.name!r}: polyline crosses itself")
        self.points = arr.tolist()

    def to_dict(self) -> dict:
        return {"kind": "JointLine", "name": self.name, "points": self.points,
                "regions": self.regions}


@dataclass
class Trace:
    """A joint line's path through one region, and the joint parts of it.

    ``coords`` is the (m, 2) polyline in the region; ``intervals`` (k, 2) are the joint parts as
    distances along it (m); the rest of the path is intact bridge.
    """

    name: str
    region: str
    coords: np.ndarray
    intervals: np.ndarray
    from_set: bool = True

    @property
    def length(self) -> float:
        return float(LineString(self.coords).length)

    def joint_pieces(self) -> list:
        """The joint parts as a list of (m, 2) polylines."""
        line = LineString(self.coords)
        out = []
        for a, b in self.intervals:
            if b - a > 0:
                out.append(np.asarray(substring(line, a, b).coords))
        return out


def traces_in_region(region_name: str, poly, joint_sets, joint_lines, tol: float | None = None) -> list:
    """All traces of the joint sets and joint lines that apply to one region polygon.

    Parts of a joint line that run along the region's boundary (within ``tol``, m; default
    1e-9 of the region size) are not traces: a free surface or a region interface is already a
    cut (e.g. a horizontal set whose spacing puts a joint exactly on a bench or on a hole edge).
    Where a trace meets a boundary vertex (it passes through a corner, or leaves the boundary
    there), that point is the vertex itself, so the cuts meet the boundary exactly.
    """
    if tol is None:
        b = poly.bounds
        tol = 1e-9 * max(1.0, float(np.hypot(b[2] - b[0], b[3] - b[1])))
    bnd = _Boundary(poly, tol)
    out = []
    for js in joint_sets:
        if js.regions is not None and region_name not in js.regions:
            continue
        for _, p0, p1, iv in js.lines(poly.bounds):
            full = LineString([p0, p1])
            for clip in _line_parts(shapely.intersection(full, poly)):
                for c in bnd.inside_runs(clip):
                    if np.dot(c[-1] - c[0], js.direction()) < 0:
                        c = c[::-1].copy()  # keep traces running down-dip, like the intervals
                    length = LineString(c).length
                    s0 = float(np.dot(c[0] - p0, js.direction()))
                    sub = np.clip(iv, s0, s0 + length) - s0
                    sub = sub[sub[:, 1] > sub[:, 0] + 1e-12 * max(length, 1.0)]
                    out.append(Trace(js.name, region_name, c, sub, True))
    for jl in joint_lines:
        if jl.regions is not None and region_name not in jl.regions:
            continue
        for clip in _line_parts(shapely.intersection(LineString(jl.points), poly)):
            for c in bnd.inside_runs(clip):
                out.append(Trace(jl.name, region_name, c, np.array([[0.0, LineString(c).length]]), False))
    return out


class _Boundary:
    """A region's boundary, for splitting clipped joint lines into their inside runs."""

    def __init__(self, poly, tol):
        self.line = poly.boundary
        shapely.prepare(self.line)
        self.vertices = shapely.get_coordinates(self.line)
        self.tol = tol

    def inside_runs(self, clip) -> list:
        """The parts of ``clip`` (a LineString in the region) not on the boundary, as (m, 2)
        arrays. Boundary vertices within ``tol`` of the line become nodes with their own exact
        coordinates; a stretch between nodes whose midpoint is on the boundary is dropped."""
        tol = self.tol
        c = np.asarray(clip.coords)
        near = self.vertices[shapely.distance(clip, shapely.points(self.vertices)) < tol]
        nodes = np.vstack([c, near])
        s = shapely.line_locate_point(clip, shapely.points(nodes))
        is_bv = np.r_[np.zeros(len(c), bool), np.ones(len(near), bool)]
        order = np.lexsort((~is_bv, s))  # boundary vertices first among equal positions
        s, nodes = s[order], nodes[order]
        keep = np.r_[True, np.diff(s) > tol]
        # a group of nodes closer than tol is represented by its first (a boundary vertex if any)
        s, nodes = s[keep], nodes[keep]
        if len(s) < 2:
            return []
        mid = shapely.line_interpolate_point(clip, 0.5 * (s[:-1] + s[1:]))
        inside = shapely.distance(self.line, mid) >= tol
        runs, cur = [], None
        for k, ok in enumerate(inside):
            if ok:
                cur = [nodes[k]] if cur is None else cur
                cur.append(nodes[k + 1])
            elif cur is not None:
                runs.append(np.asarray(cur))
                cur = None
        if cur is not None:
            runs.append(np.asarray(cur))
        return runs


def _line_parts(geom) -> list:
    """The non-empty LineStrings in a clip result (merging touching pieces)."""
    if geom.is_empty:
        return []
    if geom.geom_type == "LineString":
        return [geom]
    lines = [g for g in getattr(geom, "geoms", []) if g.geom_type == "LineString" and g.length > 0]
    if not lines:
        return []
    merged = shapely.line_merge(shapely.MultiLineString(lines))
    return [merged] if merged.geom_type == "LineString" else list(merged.geoms)
