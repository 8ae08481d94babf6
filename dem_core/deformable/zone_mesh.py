"""Zone meshes of deformable blocks: every block's polygon meshed into triangles by gmsh.

Each face of a block is split into n = ceil(L / h) equal segments (L its length, h the block's
zone size): the boundary gridpoints the contacts act on (``deformable/component.py`` finds a
point's segment on a face in O(1) because the segments of a face are equal). The interior is
meshed by gmsh's frontal-Delaunay algorithm to the size h, so a long, thin block (a column
between two joints) gets zones of about h in both directions, and a short face does not thin
the zones along the others (``zones.mesh_polygon``'s fan mesh splits every face alike, which
makes thin zones in elongated blocks and at short faces; the thinnest zone sets the time step).

All polygons are meshed in one gmsh session with the built-in kernel: the surfaces are
independent (no boolean operations), so polygons given in their own body frames may overlap.
Reference: Geuzaine & Remacle (2009), Gmsh, IJNME 79(11); the gmsh reference manual,
"Mesh.Algorithm" and transfinite curves.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["mesh_polygons", "face_segments", "check_polygon"]


def face_segments(polygon, size) -> np.ndarray:
    """(k,) int: the number of equal segments of each face of ``polygon`` (k, 2) for zone
    size ``size`` (m): ceil(L / size), at least 1."""
    poly = np.asarray(polygon, float)
    lengths = np.linalg.norm(np.roll(poly, -1, axis=0) - poly, axis=1)
    return np.maximum(1, np.ceil(lengths / size - 1e-9)).astype(np.int64)


def check_polygon(polygon, size, what) -> np.ndarray:
    """``polygon`` as a (k, 2) float array, checked: k >= 3 finite points, counter-clockwise
    with area > 0, and ``size`` > 0 m (ValueError starting with ``what``)."""
    poly = np.asarray(polygon, float)
    if poly.ndim != 2 or poly.shape[0] < 3 or poly.shape[1] != 2 or not np.isfinite(poly).all():
        raise ValueError(f"{what} must be (k >= 3, 2) finite, got shape {poly.shape}")
    if not (math.isfinite(size) and size > 0):
        raise ValueError(f"{what}: zone size must be > 0 m, got {size!r}")
    x, y = poly[:, 0], poly[:, 1]
    if not 0.5 * (x * np.roll(y, -1) - np.roll(x, -1) * y).sum() > 0:
        raise ValueError(f"{what} must be counter-clockwise with area > 0")
    return poly


def _check(polygons, sizes):
    if len(polygons) != len(sizes):
        raise ValueError(f"mesh_polygons: {len(polygons)} polygons but {len(sizes)} sizes")
    return [check_polygon(p, h, f"mesh_polygons: polygon {i}")
            for i, (p, h) in enumerate(zip(polygons, sizes))]


def mesh_polygons(polygons, sizes) -> list:
    """Mesh each polygon (k, 2), counter-clockwise, with zones of about ``sizes[i]`` m.

    Returns one (points (n, 2), triangles (m, 3) int64 counter-clockwise, faces) per polygon,
    where faces[j] is the (n_j + 1,) int64 array of the gridpoints along face j (from vertex j
    to vertex j + 1, equally spaced, ``face_segments``), points[faces[j][0]] == polygon[j].
    """
    import gmsh
    polys = _check(polygons, sizes)
    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("zones")
        gmsh.option.setNumber("Mesh.Algorithm", 6)             # frontal-Delaunay
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        surfaces = []
        for poly, h in zip(polys, sizes):
            # the corners' size h is the size inside (a block has one size)
            pts = [gmsh.model.geo.addPoint(x, y, 0.0, float(h)) for x, y in poly]
            lines = [gmsh.model.geo.addLine(pts[j], pts[(j + 1) % len(pts)])
                     for j in range(len(pts))]
            loop = gmsh.model.geo.addCurveLoop(lines)
            surfaces.append((gmsh.model.geo.addPlaneSurface([loop]), lines, float(h)))
        gmsh.model.geo.synchronize()
        for (surface, lines, h), poly in zip(surfaces, polys):
            for line, n in zip(lines, face_segments(poly, h)):
                gmsh.model.mesh.setTransfiniteCurve(line, int(n) + 1)
        gmsh.model.mesh.generate(2)
        return [_surface_mesh(gmsh, surface, poly, h)
                for (surface, _, h), poly in zip(surfaces, polys)]
    finally:
        gmsh.finalize()


def _surface_mesh(gmsh, surface, poly, h):
    tags, xyz, _ = gmsh.model.mesh.getNodes(2, surface, includeBoundary=True)
    local = {int(t): i for i, t in enumerate(tags)}
    pts = np.asarray(xyz, float).reshape(-1, 3)[:, :2]
    etypes, _, enodes = gmsh.model.mesh.getElements(2, surface)
    tri = np.asarray([local[int(t)] for t in enodes[list(etypes).index(2)]],
                     np.int64).reshape(-1, 3)
    p = pts[tri]
    cw = ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
          - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1])) < 0
    tri[cw] = tri[cw][:, [0, 2, 1]]
    pts, tri = _canonical(pts, tri)
    scale = max(float(np.abs(poly).max()), h)
    faces = []
    for j, n in enumerate(face_segments(poly, h)):
        p0, p1 = poly[j], poly[(j + 1) % len(poly)]
        along = p0 + np.outer(np.arange(n + 1) / n, p1 - p0)
        d = np.linalg.norm(pts[None, :, :] - along[:, None, :], axis=2)
        idx = d.argmin(axis=1)
        if not np.all(d[np.arange(n + 1), idx] <= 1e-7 * scale):
            raise RuntimeError(f"gmsh did not split face {j} into {n} equal segments")
        faces.append(idx.astype(np.int64))
    return pts, tri, faces


def _canonical(pts, tri):
    """The same mesh in an order that does not depend on gmsh's node numbering (which varies
    between calls in one process): points sorted by (x, y), each triangle starting at its
    lowest point (orientation kept), triangles sorted."""
    order = np.lexsort((pts[:, 1], pts[:, 0]))
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    tri = rank[tri]
    first = tri.argmin(axis=1)
    tri = np.stack([tri[np.arange(len(tri)), (first + i) % 3] for i in range(3)], axis=1)
    tri = tri[np.lexsort((tri[:, 2], tri[:, 1], tri[:, 0]))]
    return pts[order], tri
