"""From a GeometrySpec to a BlockSystem: cut, tessellate, split, conform, clean, label.

Steps
-----
1. Per region: the traces of its joint sets and joint lines.
2. Regions with a Voronoi spec: seeds (edge rows, relaxed interior), Voronoi cells clipped to
   the region, cells split along the joint segments (tips snapped to cell edges, see
   ``pieces.CellSplitter``). Regions without: cut by the full joint lines (the bridge parts of
   non-persistent sets become flaw edges, since the region has no other way to hold a bridge).
3. Non-convex pieces (from concave region corners) are cut into convex ones.
4. All pieces: shared vertex ids, T-junctions removed (``mesh``), sliver control (``slivers``).
5. Shared edges get a material: "joint:<name>" on a realized joint, "boundary:<A>|<B>" between
   regions (in region order), otherwise "flaw:<region>" (intact rock of that region).
"""
from __future__ import annotations

import time
import warnings

import numpy as np
import shapely
from shapely.geometry import LineString
from shapely.ops import substring

from .blocks import BlockSystem
from . import budget, tessellate
from .joints import traces_in_region
from .mesh import BlockMesh, polygons_to_csr
from .pieces import SIN_TOL, CellSplitter, convex_parts, is_convex, split_region_by_lines
from .slivers import remove_slivers
from .spec import GeometrySpec


def _joint_bounded_blocks(poly, traces, tol) -> tuple:
    """Cut a region without Voronoi along its full joint traces; returns (pieces, joints, n_dangling).

    Each trace is cut into its joint and bridge parts (so both get their own edges); cut points
    closer than ``tol`` (m) are one point (a joint ending at the region boundary up to round-off
    would otherwise leave a zero-length bridge).
    """
    lines, joints = [], []
    for t in traces:
        line = LineString(t.coords)
        cuts = np.unique(np.r_[0.0, t.intervals.ravel(), line.length])
        cuts = cuts[np.r_[True, np.diff(cuts) > tol]]
        cuts[-1] = line.length
        lines += [np.asarray(substring(line, a, b).coords) for a, b in zip(cuts[:-1], cuts[1:]) if b > a]
        joints += [(t.name, c) for c in t.joint_pieces()]
    pieces, n_dangling = split_region_by_lines(poly, lines, tol)
    return [q for p in pieces for q in convex_parts(p)], joints, n_dangling


def _voronoi_blocks(poly, traces, vs) -> tuple:
    """Tessellate a region and split its cells along the joints; returns (pieces, joints)."""
    joint_pieces = [(t.name, c) for t in traces for c in t.joint_pieces()]
    seeds = tessellate.seeds(poly, [c for _, c in joint_pieces], vs)
    inside, clipped = tessellate.voronoi_cells(poly, seeds)
    parts = []
    for p in clipped:
        parts += [p] if is_convex(np.asarray(shapely.orient_polygons(p).exterior.coords)[:-1]) \
            and not p.interiors else convex_parts(p)
    cells = np.concatenate([inside, np.asarray(parts, dtype=object)]) if parts else inside
    if not joint_pieces:
        return cells, []
    splitter = CellSplitter(poly, cells)
    realized = []
    for name, c in joint_pieces:
        r = splitter.realize(c)
        if r is not None:
            splitter.cut(r)
            realized.append((name, r))
    return splitter.current_pieces(), realized


def _edge_materials(mesh, shared, region_names, joint_names, joints, tol) -> tuple:
    """Material name index per shared edge (see module docstring).

    ``material_names`` always lists every region's flaw and every joint set/line (used or not),
    then the region-boundary pairs that occur.
    """
    names = [f"flaw:{r}" for r in region_names] + [f"joint:{n}" for n in joint_names]
    reg = np.asarray(mesh.region)
    ra, rb = reg[shared[:, 0]], reg[shared[:, 1]]
    mat = ra.copy()  # flaw of the region by default
    cross = ra != rb
    pairs = sorted({(min(a, b), max(a, b)) for a, b in zip(ra[cross], rb[cross])})
    for a, b in pairs:
        names.append(f"boundary:{region_names[a]}|{region_names[b]}")
        m = cross & (np.minimum(ra, rb) == a) & (np.maximum(ra, rb) == b)
        mat[m] = len(names) - 1
    if joints and len(shared):
        segs, seg_name = [], []
        for n, c in joints:
            segs += [c[i:i + 2] for i in range(len(c) - 1)]
            seg_name += [names.index(f"joint:{n}")] * (len(c) - 1)
        seg_geom = shapely.linestrings(np.asarray(segs))
        tree = shapely.STRtree(seg_geom)
        p0, p1 = mesh.X[shared[:, 2]], mesh.X[shared[:, 3]]
        ei, si = tree.query(shapely.points(0.5 * (p0 + p1)), predicate="dwithin", distance=tol)
        on = (shapely.distance(seg_geom[si], shapely.points(p0[ei])) < tol) & \
             (shapely.distance(seg_geom[si], shapely.points(p1[ei])) < tol)
        mat[ei[on]] = np.asarray(seg_name)[si[on]]
    return mat.astype(np.int32), names


def _groups(spec, region_id, centroid) -> dict:
    groups = {}
    for i, r in enumerate(spec.regions):
        members = np.nonzero(region_id == i)[0].astype(np.int64)
        groups[r.name] = members
        for g in r.groups:
            groups[g] = np.union1d(groups.get(g, np.zeros(0, np.int64)), members).astype(np.int64)
    for g, ring in spec.groups.items():
        poly = shapely.Polygon(ring)
        inside = shapely.contains_xy(poly, centroid[:, 0], centroid[:, 1])
        groups[g] = np.union1d(groups.get(g, np.zeros(0, np.int64)), np.nonzero(inside)[0]).astype(np.int64)
    return groups


def build_block_system(spec: GeometrySpec, max_blocks: int | None = None) -> BlockSystem:
    """Build the blocks and their shared edges from a scene geometry.

    Parameters
    ----------
    spec : GeometrySpec
        Validated again before any compute (ValueError names the bad value).
    max_blocks : int, optional
        Refuse a geometry estimated at more blocks (default: the environment variable
        ``DEM_MAX_BLOCKS``, if set); one that would need more memory than the machine has
        available is always refused (``budget.check_size``, ValueError with the numbers).

    Returns
    -------
    BlockSystem
        Convex CCW blocks tiling the regions exactly, shared edges with materials. ``meta``
        holds the build time (s), the realized joint segments, the trace lengths per joint
        set/line, the sliver-control counts and any warnings.
    """
    spec.validate()
    budget.check_size(spec, max_blocks)
    t_start = time.perf_counter()
    polys = [r.polygon() for r in spec.regions]
    region_names = [r.name for r in spec.regions]
    b = np.array([p.bounds for p in polys])
    tol = 1e-9 * max(1.0, float(np.hypot(b[:, 2].max() - b[:, 0].min(), b[:, 3].max() - b[:, 1].min())))
    pieces, piece_region, joints, trace_len, notes = [], [], [], {}, []
    for ri, (r, poly) in enumerate(zip(spec.regions, polys)):
        traces = traces_in_region(r.name, poly, spec.joint_sets, spec.joints, tol)
        for t in traces:
            trace_len[t.name] = trace_len.get(t.name, 0.0) + t.length
        vs = spec.voronoi.get(r.name)
        if vs is None:
            ps, js, n_dangling = _joint_bounded_blocks(poly, traces, tol)
            if n_dangling:
                notes.append(f"region {r.name!r}: {n_dangling} joint line part(s) end inside a "
                             "block without Voronoi flaws and cut nothing")
        else:
            ps, js = _voronoi_blocks(poly, traces, vs)
        pieces += list(ps)
        piece_region += [ri] * len(ps)
        joints += js
    for n in notes:
        warnings.warn(n)
    xy, off = polygons_to_csr(pieces)
    mesh = BlockMesh.from_csr(xy, off, piece_region, tol)
    sliver_log = remove_slivers(mesh, spec, polys, joints)
    return _assemble(mesh, spec, region_names, joints, tol, {
        "build_seconds": time.perf_counter() - t_start, "tolerance": tol,
        "joint_segments": joints, "trace_length": trace_len, "slivers": sliver_log,
        "warnings": notes})


def _check_blocks(xy, off, area) -> None:
    """Every block CCW with positive area and convex; else a RuntimeError naming the block."""
    owner = np.repeat(np.arange(len(off) - 1), np.diff(off))
    nxt = np.arange(len(xy)) + 1
    nxt[off[1:] - 1] = off[:-1]
    e = xy[nxt] - xy
    en = e[nxt]
    cross = e[:, 0] * en[:, 1] - e[:, 1] * en[:, 0]
    bad = cross < -SIN_TOL * np.hypot(*e.T) * np.hypot(*en.T)
    if np.any(area <= 0) or np.any(bad):
        b = int(np.nonzero(area <= 0)[0][0]) if np.any(area <= 0) else int(owner[bad][0])
        raise RuntimeError(f"block {b} is not convex/CCW (area {area[b]:.3g}): {xy[off[b]:off[b+1]]}"
                           " - a bug in the geometry build")


def _assemble(mesh, spec, region_names, joints, tol, meta) -> BlockSystem:
    ids, off = mesh.csr()
    verts = mesh.X[ids]
    area, cen = mesh.area_centroid()
    edges = mesh.edge_table()
    shared = edges["shared"]
    p0, p1 = mesh.X[shared[:, 2]], mesh.X[shared[:, 3]]
    d = p1 - p0
    length = np.hypot(d[:, 0], d[:, 1])
    normal = np.column_stack([d[:, 1], -d[:, 0]]) / length[:, None]  # right of A's CCW edge
    _check_blocks(verts, off, area)
    joint_names = [j.name for j in spec.joint_sets] + [j.name for j in spec.joints]
    mat, names = _edge_materials(mesh, shared, region_names, joint_names, joints, tol)
    region_id = np.asarray(mesh.region, np.int32)
    meta["free_edges"] = {"block": edges["free"][:, 0], "p0": mesh.X[edges["free"][:, 1]],
                          "p1": mesh.X[edges["free"][:, 2]]}
    return BlockSystem(
        vertices=verts, vertex_offsets=off, centroid=cen, area=area, region_id=region_id,
        region_names=list(region_names), groups=_groups(spec, region_id, cen),
        edge_p0=p0, edge_p1=p1, edge_block_a=shared[:, 0].astype(np.int64),
        edge_block_b=shared[:, 1].astype(np.int64), edge_normal=normal, edge_length=length,
        edge_material=mat, material_names=names, meta=meta)
