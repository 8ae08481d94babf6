"""Cutting polygons: convex parts, regions cut by joint traces, Voronoi cells split by joints."""
from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon
from shapely.ops import split

SIN_TOL = 1e-9  # |sin| of a turn below which a vertex counts as straight


def is_convex(xy: np.ndarray) -> bool:
    """True if the closed CCW polygon ``xy`` (no repeated end point) turns left (or straight)."""
    e = np.roll(xy, -1, axis=0) - xy
    ln = np.hypot(e[:, 0], e[:, 1])
    if np.any(ln == 0):
        return False
    en = np.roll(e, -1, axis=0)
    cross = e[:, 0] * en[:, 1] - e[:, 1] * en[:, 0]
    return bool(np.all(cross >= -SIN_TOL * ln * np.roll(ln, -1)))


def _ring(poly) -> np.ndarray:
    return np.asarray(shapely.orient_polygons(poly).exterior.coords)[:-1]


def _drop_degenerate_vertices(xy: np.ndarray, tol: float) -> np.ndarray:
    """Remove round-off debris from a ring: a vertex within ``tol`` (m) of the previous one,
    or the tip of a zero-width spike (its two neighbours within ``tol`` of each other). GEOS
    overlays leave such spikes where a clipped or split line passes a hair from a corner."""
    pts = [p for p in xy]
    changed = True
    while changed and len(pts) >= 3:
        changed = False
        for i in range(len(pts)):
            prev, nxt = pts[i - 1], pts[(i + 1) % len(pts)]
            if np.hypot(*(pts[i] - prev)) < tol or np.hypot(*(nxt - prev)) < tol:
                del pts[i]
                changed = True
                break
    return np.asarray(pts).reshape(-1, 2)


def convex_parts(poly: Polygon) -> list:
    """Split a polygon (holes allowed) into convex polygons.

    Holes: cut by the vertical line through the hole's centre. Reflex vertex: cut along the
    extension of its incoming edge (the ray leaves both sides with angles <= 180 degrees).
    """
    poly = shapely.orient_polygons(poly)
    if poly.interiors:
        c = np.asarray(poly.interiors[0].centroid.coords)[0]
        ymin, ymax = poly.bounds[1] - 1.0, poly.bounds[3] + 1.0
        parts = split(poly, LineString([(c[0], ymin), (c[0], ymax)])).geoms
        return [q for p in parts for q in convex_parts(p)]
    xy = _ring(poly)
    clean = _drop_degenerate_vertices(xy, 1e-9 * max(1.0, float(np.hypot(*np.ptp(xy, axis=0)))))
    if len(clean) < len(xy):
        if len(clean) < 3:
            return []
        xy, poly = clean, Polygon(clean)
    if is_convex(xy):
        return [poly]
    e = np.roll(xy, -1, axis=0) - xy
    ep = np.roll(e, 1, axis=0)
    cross = ep[:, 0] * e[:, 1] - ep[:, 1] * e[:, 0]
    i = int(np.argmin(cross / (np.hypot(*e.T) * np.hypot(*ep.T))))
    d = ep[i] / np.hypot(*ep[i])
    size = np.hypot(poly.bounds[2] - poly.bounds[0], poly.bounds[3] - poly.bounds[1])
    ray = LineString([xy[i], xy[i] + 2.0 * size * d])
    parts = [p for p in split(poly, ray).geoms if p.area > 0]
    if len(parts) < 2:  # numerical corner case: cut through the vertex in the other direction
        dn = e[i] / np.hypot(*e[i])
        parts = [p for p in split(poly, LineString([xy[i], xy[i] - 2.0 * size * dn])).geoms
                 if p.area > 0]
        if len(parts) < 2:
            raise RuntimeError(f"could not split non-convex polygon {poly.wkt[:200]}")
    return [q for p in parts for q in convex_parts(p)]


def split_region_by_lines(poly: Polygon, lines: list, tol: float) -> tuple:
    """Cut a region by polylines (node them with its boundary, polygonize).

    A line end within ``tol`` (m) of a boundary edge (but not exactly at a boundary vertex) is
    pushed 100 ``tol`` outwards along the line: a trace clipped to the region ends on a sloping
    boundary segment only up to round-off, and an end a hair inside would not be noded with
    the boundary, so the line would cut nothing. Returns (pieces, dangling): the polygons that tile the region and the
    number of line parts that end inside it (the stubs pushed outside are not counted).
    """
    if not lines:
        return [poly], 0
    bnd = poly.boundary
    corners = {tuple(v) for v in shapely.get_coordinates(bnd)}
    out_lines = []
    for c in lines:
        c = np.array(c, float)
        for end, nxt in ((0, 1), (-1, -2)):
            if tuple(c[end]) not in corners and bnd.distance(Point(c[end])) < tol:
                d = c[end] - c[nxt]
                c[end] += 100.0 * tol * d / np.hypot(*d)
        out_lines.append(LineString(c))
    linework = shapely.union_all([bnd] + out_lines)
    polys, _, dangles, _ = shapely.polygonize_full([linework])
    out = [p for p in shapely.get_parts(polys) if p.area > 0
           and poly.contains(p.representative_point())]
    dangles = shapely.get_parts(dangles)
    return out, int(np.count_nonzero(shapely.length(dangles) > 150.0 * tol))


class CellSplitter:
    """Split convex pieces (Voronoi cells) along joint segments, snapping joint tips.

    A joint tip inside a cell is moved along the joint line to the nearer end of the chord the
    line makes through that cell (extended or trimmed by less than one cell), so every joint
    edge lies exactly on the trace and no cell is cut half way.
    """

    def __init__(self, poly: Polygon, pieces):
        self.poly = poly
        self.tol = 1e-9 * max(1.0, np.hypot(poly.bounds[2] - poly.bounds[0], poly.bounds[3] - poly.bounds[1]))
        self.pieces = list(pieces)
        self.alive = [True] * len(self.pieces)
        self.children = [[i] for i in range(len(self.pieces))]  # per original cell
        self.root = list(range(len(self.pieces)))                # original cell of a piece
        self.tree = shapely.STRtree(self.pieces)

    def _current(self, geom, predicate="intersects"):
        out = []
        for r in self.tree.query(geom, predicate=predicate):
            out += [i for i in self.children[r] if self.alive[i]]
        return out

    def _snap_tip(self, tip, direction):
        """New position of a joint tip: the nearer end of the chord through its cell.

        The chord is where the joint's line crosses the cell, or runs along one of its edges
        (when the cells already follow the joint); a tip already at a chord end stays.
        """
        if self.poly.boundary.distance(Point(tip)) < self.tol:
            return tip
        for i in self._current(Point(tip).buffer(self.tol)):
            pc = self.pieces[i]
            big = 4.0 * np.sqrt(pc.area + pc.length ** 2)
            chord = pc.intersection(LineString([tip - big * direction, tip + big * direction]))
            if chord.is_empty or chord.length <= self.tol:
                continue
            for part in getattr(chord, "geoms", [chord]):
                if part.geom_type != "LineString":
                    continue
                sv = (np.asarray(part.coords) - tip) @ direction
                if sv.min() < -self.tol and sv.max() > self.tol:
                    return tip + (sv.min() if -sv.min() < sv.max() else sv.max()) * direction
        return tip

    def realize(self, coords: np.ndarray) -> np.ndarray | None:
        """Snap both tips of a joint polyline; None if it shrinks to nothing."""
        c = np.array(coords, float)
        for end, nxt in ((0, 1), (-1, -2)):
            d = c[end] - c[nxt]
            d /= np.hypot(*d)
            new = self._snap_tip(c[end], d)
            # trimming must not pass the next polyline vertex
            if (new - c[nxt]) @ d <= self.tol:
                if len(c) == 2:
                    return None
                new = c[end]
            c[end] = new
        if LineString(c).length < self.tol:
            return None
        return c

    def cut(self, coords: np.ndarray) -> None:
        """Split every piece the joint polyline crosses (ends pushed 100 tol outwards so a tip
        that lies on a cell edge up to round-off still cuts that cell through)."""
        c = np.array(coords, float)
        for end, nxt in ((0, 1), (-1, -2)):
            d = c[end] - c[nxt]
            c[end] += 100.0 * self.tol * d / np.hypot(*d)
        line = LineString(c)
        for i in self._current(line):
            pc = self.pieces[i]
            if pc.intersection(line).length <= self.tol:
                continue
            parts = [p for p in split(pc, line).geoms if p.area > 0]
            if len(parts) < 2:
                continue
            self.alive[i] = False
            root = self.root[i]
            for p in parts:
                for q in convex_parts(p):
                    self.pieces.append(q)
                    self.alive.append(True)
                    self.root.append(root)
                    self.children[root].append(len(self.pieces) - 1)

    def current_pieces(self) -> list:
        return [p for p, a in zip(self.pieces, self.alive) if a]
