"""The rupture surface: the connected path of broken flaws through the rock, from a crack log.

A rupture surface in the damage model is a continuous path of broken contacts (thesis ch. 4:
"a continuous rupture surface of broken flaws forms"). Across a joint the path jumps from one
column to the next, so cracks are linked by distance, not by shared block edges:

1. cracks (x, y) closer than ``link_distance`` (about 1.5 block edge lengths) are linked;
2. the connected groups are found (scipy.sparse.csgraph) and the largest one is the rupture
   (or the largest that comes within ``link_distance`` of a given free-face segment);
3. its polyline is the mean crack position in bins of ``link_distance`` along the group's
   principal direction, ordered from the face (if given) inwards.

Angles are in degrees; positive ``angle_above_joint_normal`` means the rupture rises more
steeply (going into the slope) than the normal to the joints, as in Adhikary et al.'s "12 to 20
degrees above the normal to the joints".
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

__all__ = ["RuptureSurface", "find_rupture", "angle_to_joint_normal", "path_at_angle",
           "depth_from_face"]


@dataclass
class RuptureSurface:
    """polyline : (n, 2) m, from the face inwards; crack_index : cracks in the rupture group;
    length : m along the polyline; direction : unit vector of the principal axis (face -> in)."""

    polyline: np.ndarray
    crack_index: np.ndarray
    length: float
    direction: np.ndarray

    @property
    def n_cracks(self) -> int:
        return int(self.crack_index.size)


def find_rupture(x, y, link_distance, face=None, min_cracks=3):
    """The largest connected group of cracks as a polyline (module docstring), or None.

    Parameters
    ----------
    x, y : (n,) crack positions, m.
    link_distance : float, m. Two cracks closer than this are connected (> 0).
    face : ((x0, y0), (x1, y1)), optional. The free face: the rupture must reach it, and the
        polyline is ordered from it inwards.
    min_cracks : int. Fewer cracks in the group: no rupture (None).
    """
    if not (link_distance > 0 and math.isfinite(link_distance)):
        raise ValueError(f"link_distance must be a finite length > 0 m, got {link_distance!r}")
    pts = np.column_stack([np.asarray(x, float), np.asarray(y, float)])
    if len(pts) < min_cracks:
        return None
    pairs = cKDTree(pts).query_pairs(link_distance, output_type="ndarray")
    n = len(pts)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    sizes = np.bincount(label)
    order = np.argsort(-sizes, kind="stable")
    for group in order:
        if sizes[group] < min_cracks:
            return None
        members = np.flatnonzero(label == group)
        if face is None or _distance_to_segment(pts[members], *face).min() <= link_distance:
            return _polyline(pts, members, link_distance, face)
    return None


def _polyline(pts, members, bin_width, face):
    p = pts[members]
    centre = p.mean(axis=0)
    _, _, vt = np.linalg.svd(p - centre, full_matrices=False)
    axis = vt[0]
    if face is not None:
        # orient from the face inwards: the end nearer the face comes first
        t = (p - centre) @ axis
        near = _distance_to_segment(p, *face)
        if near[np.argmax(t)] < near[np.argmin(t)]:
            axis = -axis
    t = (p - centre) @ axis
    bins = np.floor((t - t.min()) / bin_width).astype(np.int64)
    line = np.array([p[bins == k].mean(axis=0) for k in np.unique(bins)])
    length = float(np.hypot(*np.diff(line, axis=0).T).sum()) if len(line) > 1 else 0.0
    return RuptureSurface(line, members, length, axis)


def _distance_to_segment(p, a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    ab = b - a
    t = np.clip(((p - a) @ ab) / (ab @ ab), 0.0, 1.0)
    return np.hypot(*(p - (a + t[:, None] * ab)).T)


def angle_to_joint_normal(direction, joint_dip_deg, dip_direction="left"):
    """Angle (deg) of a rupture direction above the normal to a joint set.

    ``direction`` is the rupture's unit vector pointing into the rock mass. The joint normal
    taken is the one pointing the same way horizontally. Positive: the rupture rises more
    steeply than the normal (it lies "above" it going inwards).

    ``dip_direction``: "left" when the joints go down towards -x (into a slope facing +x).
    """
    d = np.asarray(direction, float)
    d = d / np.hypot(*d)
    dip = math.radians(joint_dip_deg)
    sx = -1.0 if dip_direction == "left" else 1.0
    joint = np.array([sx * math.cos(dip), -math.sin(dip)])       # down-dip unit vector
    normal = np.array([-joint[1], joint[0]])
    if normal[0] * d[0] < 0 or (normal[0] == 0 and normal[1] * d[1] < 0):
        normal = -normal
    rise = lambda v: math.degrees(math.atan2(v[1], abs(v[0])))  # noqa: E731
    return rise(d) - rise(normal)


def path_at_angle(start, joint_dip_deg, angle_deg, length, inward=-1.0,
                  dip_direction="left"):
    """A straight path (2, 2) m from ``start`` into the rock at ``angle_deg`` above the normal to
    a joint set: the inverse of ``angle_to_joint_normal`` (same convention), e.g. an
    experiment's fracture path "12 to 20 degrees above the normal to the joints" drawn from the
    toe. ``inward``: the sign of x going into the rock (-1 for a slope facing +x); ``length``
    (m) along the path."""
    if inward not in (-1.0, 1.0, -1, 1) or not length > 0:
        raise ValueError(f"path_at_angle: inward must be -1 or 1 (got {inward!r}) and length "
                         f"positive (got {length!r})")
    dip = math.radians(joint_dip_deg)
    sx = -1.0 if dip_direction == "left" else 1.0
    normal = np.array([math.sin(dip), sx * math.cos(dip)])        # normal to the down-dip vector
    if normal[0] * inward < 0:
        normal = -normal
    rise = math.atan2(normal[1], abs(normal[0])) + math.radians(angle_deg)
    a = np.asarray(start, float)
    return np.array([a, a + length * np.array([inward * math.cos(rise), math.sin(rise)])])


def depth_from_face(polyline, face):
    """Largest normal distance (m) of the rupture polyline from the face line (its depth)."""
    a, b = (np.asarray(v, float) for v in face)
    ab = b - a
    n = np.array([-ab[1], ab[0]]) / np.hypot(*ab)
    return float(np.abs((np.asarray(polyline) - a) @ n).max())
