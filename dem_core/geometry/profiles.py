"""Regions for common scenes: slope and multi-bench profiles, and a zone along the face.

Coordinates (m): the origin is at the bottom-left corner of the model, x to the right, y up.
By default (``facing="right"``, the toolkit convention, see ``joints``) the slope faces +x: the
crest is at the left from x = 0, the face goes down to the right, the toe bench runs to the
right edge of the model, and ``base_thickness`` of rock lies under the toe level. With this
orientation joints dipping *into* the slope are ``JointSet(..., dip_direction="left")``.
``facing="left"`` mirrors the model about its vertical centre line (toe bench at the left from
x = 0, crest to the right; joints into the slope are then ``dip_direction="right"``).

The thesis puts Voronoi flaws only in a band near the face; ``near_face_regions`` splits a
profile into that band and the rest, two Regions sharing a boundary, so that a scene can
tessellate the band (``Voronoi``) and leave the rest joint-bounded (coarse blocks).
"""
from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import Polygon

from .regions import Region


def _check(name, value, positive=True) -> float:
    v = float(value)
    if not np.isfinite(v) or (v <= 0 if positive else v < 0):
        raise ValueError(f"{name} must be finite and {'> 0' if positive else '>= 0'}, got {value!r}")
    return v


def _face_run(height, dip, what) -> float:
    """Horizontal run (m) of a face of ``height`` dipping ``dip`` degrees (0 < dip <= 90)."""
    if not 0.0 < dip <= 90.0:
        raise ValueError(f"{what} must be in (0, 90] degrees, got {dip}")
    return 0.0 if dip == 90.0 else height / np.tan(np.radians(dip))


def _profile_region(faces, berms, crest_length, toe_length, base_thickness, name, facing,
                    groups) -> Region:
    """Region of a profile with faces [(height, run)] from the crest down, berms between them."""
    if facing not in ("right", "left"):
        raise ValueError(f"facing must be 'right' or 'left', got {facing!r}")
    crest_length = _check("crest_length", crest_length, positive=False)
    toe_length = _check("toe_length", toe_length, positive=False)
    base_thickness = _check("base_thickness", base_thickness, positive=False)
    # levels summed from the toe up, so the toe level is exactly base_thickness
    levels = base_thickness + np.r_[0.0, np.cumsum([h for h, _ in faces[::-1]])][::-1]
    x, y = crest_length, levels[0]
    surface = [(0.0, y), (x, y)]           # crest ... toe, facing right
    for k, (h, run) in enumerate(faces):
        x, y = x + run, levels[k + 1]
        surface.append((x, y))
        if k < len(berms):
            x += berms[k]
            surface.append((x, y))
    width = x + toe_length
    surface.append((width, y))
    ring = [(0.0, 0.0), (width, 0.0)] + surface[::-1]
    if facing == "left":
        ring = [(width - px, py) for px, py in ring[::-1]]
    # drop repeated points (zero crest/toe/base lengths) so the ring stays valid
    out = [p for i, p in enumerate(ring) if np.hypot(p[0] - ring[i - 1][0], p[1] - ring[i - 1][1]) > 0]
    return Region(name, out, groups=list(groups))


def slope_profile(height, face_dip_deg, crest_length, toe_length, base_thickness, name="rock",
                  facing="right", groups=()) -> Region:
    """A single-face slope as a Region (see the module docstring for the coordinates).

    Parameters
    ----------
    height : float
        Face height from the toe level to the crest, m (> 0).
    face_dip_deg : float
        Face angle from horizontal, degrees, in (0, 90] (90: vertical face).
    crest_length, toe_length : float
        Horizontal length of the crest (behind the face) and of the toe bench (in front of it), m
        (>= 0).
    base_thickness : float
        Rock under the toe level, m (>= 0).
    name : str
        Region name.
    facing : {"right", "left"}
        Which way the face looks (default +x, the toolkit convention).
    groups : sequence of str
        Extra group names of the region.

    Returns
    -------
    Region
        Area = width * base_thickness + crest_length * height + height * run / 2 with
        run = height / tan(face_dip_deg) and width = crest_length + run + toe_length.
    """
    height = _check("height", height)
    run = _face_run(height, float(face_dip_deg), "face_dip_deg")
    return _profile_region([(height, run)], [], crest_length, toe_length, base_thickness, name,
                           facing, groups)


def bench_profile(bench_height, n_benches, face_dip_deg, berm_width, crest_length, toe_length,
                  base_thickness, name="rock", facing="right", groups=()) -> Region:
    """A benched slope: ``n_benches`` equal faces separated by horizontal berms.

    Parameters as in ``slope_profile``; ``bench_height`` (m, > 0) is the height of each face and
    ``berm_width`` (m, > 0) the horizontal width of each of the ``n_benches - 1`` berms. The
    overall slope angle (toe to crest) is atan(H / (n run + (n - 1) berm_width)) with
    H = n bench_height and run = bench_height / tan(face_dip_deg).
    """
    bench_height = _check("bench_height", bench_height)
    berm_width = _check("berm_width", berm_width)
    if int(n_benches) != n_benches or n_benches < 1:
        raise ValueError(f"n_benches must be an integer >= 1, got {n_benches!r}")
    n = int(n_benches)
    run = _face_run(bench_height, float(face_dip_deg), "face_dip_deg")
    return _profile_region([(bench_height, run)] * n, [berm_width] * (n - 1), crest_length,
                           toe_length, base_thickness, name, facing, groups)


def _surface_parts(poly: Polygon, tol: float) -> tuple:
    """Faces (inclined or vertical edges) and berms (horizontal edges) of the free surface.

    The free surface is the exterior ring without the edges on the model's left, right and
    bottom sides (the bounding box); returned as lists of (p0, p1) with p0 the lower end (faces)
    or the left end (berms), excluding the outermost horizontal edges (crest and toe bench).
    """
    xmin, ymin, xmax, ymax = poly.bounds
    c = np.asarray(poly.exterior.coords)
    faces, flats = [], []
    for p, q in zip(c[:-1], c[1:]):
        on_box = (abs(p[0] - q[0]) < tol and (abs(p[0] - xmin) < tol or abs(p[0] - xmax) < tol)) \
            or (abs(p[1] - ymin) < tol and abs(q[1] - ymin) < tol)
        if on_box:
            continue
        if abs(p[1] - q[1]) < tol:
            flats.append((min(p[0], q[0]), max(p[0], q[0]), p[1]))
        else:
            faces.append((p, q) if p[1] < q[1] else (q, p))
    if not faces:
        raise ValueError("the region has no face: no inclined or vertical edge on its free surface")
    lo = min(f[0][1] for f in faces)
    hi = max(f[1][1] for f in faces)
    berms = [(x0, x1, y) for x0, x1, y in flats if lo + tol < y < hi - tol]
    return faces, berms


def zone_polygon_along_face(region: Region, depth: float) -> list:
    """The rock within normal distance ``depth`` (m) of the slope face(s), as a ring of (x, y).

    Behind each face (an inclined or vertical edge of the free surface, i.e. of the exterior
    ring off the model's bounding box) the zone is the parallelogram between the face's toe and
    crest levels whose inner side is parallel to the face at normal distance ``depth``
    (horizontal offset depth / sin(dip)); under each berm between two faces it is the strip of
    thickness ``depth``, continued under the band of the face above the berm (so the zone is one
    polygon). The crest and the toe bench are not part of it. Area for one face of height
    H: depth * H / sin(dip).

    Raises ValueError if the zone leaves the region (``depth`` too large for the model) or
    falls apart.
    """
    depth = _check("depth", depth)
    poly = region.polygon()
    b = poly.bounds
    tol = 1e-9 * max(1.0, float(np.hypot(b[2] - b[0], b[3] - b[1])))
    faces, berms = _surface_parts(poly, tol)
    parts, toe_offset = [], []
    for p, q in faces:
        sin_dip = abs(q[1] - p[1]) / np.hypot(*(q - p))
        mid = 0.5 * (p + q)
        side = -1.0 if poly.contains(shapely.Point(mid[0] - 1e3 * tol, mid[1])) else 1.0
        s = np.array([side * depth / sin_dip, 0.0])  # horizontal, into the rock
        parts.append(Polygon([p, q, q + s, p + s]))
        toe_offset.append((p, s[0]))
    for x0, x1, y in berms:
        parts.append(Polygon([(x0, y), (x1, y), (x1, y - depth), (x0, y - depth)]))
        # the re-entrant corner where the berm meets the toe of the face above: the berm strip
        # goes on under that face's band (else the two would touch at a point only)
        for p, e in toe_offset:
            for x in (x0, x1):
                if abs(p[1] - y) < tol and abs(p[0] - x) < tol:
                    parts.append(Polygon([(x, y), (x + e, y), (x + e, y - depth), (x, y - depth)]))
    zone = shapely.union_all(parts)
    if not poly.buffer(tol).contains(zone):
        raise ValueError(f"depth {depth} m: the zone along the face leaves the region "
                         "(make the model wider/deeper or the zone thinner)")
    zone = poly.intersection(zone)
    if zone.geom_type != "Polygon" or zone.interiors:
        raise ValueError(f"depth {depth} m: the zone along the face is not one simple polygon")
    return [tuple(map(float, xy)) for xy in np.asarray(shapely.orient_polygons(zone).exterior.coords)[:-1]]


def near_face_regions(region: Region, depth: float, zone_name: str = "face_zone",
                      zone_groups=(), rest_groups=()) -> tuple:
    """Split a profile into the zone along its face and the rest: ``(zone, rest)`` Regions.

    The zone is ``zone_polygon_along_face(region, depth)``; ``rest`` keeps the region's name,
    holes and groups. The two share a boundary (an interface: "boundary:<A>|<B>" contacts).
    """
    ring = zone_polygon_along_face(region, depth)
    poly = region.polygon()
    rest = poly.difference(Polygon(ring))
    if rest.geom_type != "Polygon":
        raise ValueError(f"depth {depth} m: the rock outside the zone along the face falls apart "
                         f"({rest.geom_type}); use a thinner zone or split the region yourself")
    rest = shapely.orient_polygons(rest)
    zone_region = Region(zone_name, ring, groups=list(zone_groups))
    rest_region = Region(region.name, np.asarray(rest.exterior.coords)[:-1].tolist(),
                         holes=[np.asarray(h.coords)[:-1].tolist() for h in rest.interiors],
                         groups=list(region.groups) + list(rest_groups))
    return zone_region, rest_region
