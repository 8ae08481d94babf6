"""Sliver control: no block or edge so small that it wrecks the DEM time step.

Applied to blocks of Voronoi regions only (joint-bounded blocks are what the joints make).
With h the local target edge length of the block's region:

1. Small blocks (area < ``min_area_fraction * h^2``) are merged into a neighbour of the same
   region across a flaw edge when the union is convex (largest shared edge first).
2. Short edges (length < ``min_edge_fraction * h``) are collapsed by merging their two end
   vertices. Free vertices meet at the midpoint; a vertex on a region boundary or a joint keeps
   its place (the free one moves to it); two vertices on the same straight boundary/joint
   segment meet at their midpoint on it; corners and joint tips never move. A collapse that
   would make any block non-convex is skipped. Blocks that become degenerate (a triangle whose
   short edge collapses) vanish; their area passes to the neighbours.

Both steps keep the blocks an exact partition of the regions, so the areas still sum to the
region areas. Edges that cannot be removed this way stay, and are counted in the log.
"""
from __future__ import annotations

from collections import defaultdict

import numpy as np
import shapely

from .pieces import SIN_TOL


class _Constraints:
    """Which straight segments (region rings, joints) a vertex lies on."""

    def __init__(self, polys, joints, tol):
        segs = []
        for p in polys:
            for ring in [p.exterior] + list(p.interiors):
                c = np.asarray(ring.coords)
                segs += [c[i:i + 2] for i in range(len(c) - 1)]
        for _, c in joints:
            segs += [c[i:i + 2] for i in range(len(c) - 1)]
        self.segs = np.asarray(segs, float).reshape(-1, 2, 2)
        self.tree = shapely.STRtree(shapely.linestrings(self.segs))
        self.tol = tol

    def on(self, xy) -> set:
        return set(self.tree.query(shapely.Point(xy), predicate="dwithin", distance=self.tol).tolist())

    def is_end(self, xy, segs) -> bool:
        return any(np.min(np.hypot(*(self.segs[s] - xy).T)) < self.tol for s in segs)


def _straight_pair(segs_a, segs_b, cons) -> bool:
    """True if all the segments are collinear (one straight line)."""
    s = list(segs_a | segs_b)
    d0 = cons.segs[s[0], 1] - cons.segs[s[0], 0]
    for k in s[1:]:
        d = cons.segs[k, 1] - cons.segs[k, 0]
        if abs(d0[0] * d[1] - d0[1] * d[0]) > 1e-9 * np.hypot(*d0) * np.hypot(*d):
            return False
    return True


def _dedupe(loop):
    out = [v for k, v in enumerate(loop) if v != loop[k - 1]] if len(loop) > 1 else list(loop)
    return out


def _merge_loops(a, b, u, v):
    """Union of block loops a (with edge u->v) and b (with v->u), or None if not simple."""
    k = next(i for i in range(len(a)) if a[i] == u and a[(i + 1) % len(a)] == v)
    m = next(i for i in range(len(b)) if b[i] == v and b[(i + 1) % len(b)] == u)
    ar = a[k + 1:] + a[:k + 1]   # v ... u
    br = b[m + 1:] + b[:m + 1]   # u ... v
    loop = ar + br[1:-1]
    changed = True
    while changed and len(loop) >= 3:  # remove spikes x, y, x left by a longer shared chain
        changed = False
        for i in range(len(loop)):
            if loop[i - 1] == loop[(i + 1) % len(loop)]:
                j = (i + 1) % len(loop)
                loop = [w for t, w in enumerate(loop) if t not in (i, j)]
                changed = True
                break
    if len(loop) < 3 or len(set(loop)) != len(loop):
        return None
    return loop


def _area(xy):
    """Signed area of a small polygon (plain Python: faster than numpy for a few vertices)."""
    pts = xy.tolist()
    x0, y0 = pts[0]
    a = 0.0
    for (x1, y1), (x2, y2) in zip(pts, pts[1:] + pts[:1]):
        a += (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
    return 0.5 * a


def _convex(xy) -> bool:
    """Same test as ``pieces.is_convex`` (left or straight turns only), in plain Python."""
    pts = xy.tolist()
    n = len(pts)
    for i in range(n):
        (x0, y0), (x1, y1), (x2, y2) = pts[i - 1], pts[i], pts[(i + 1) % n]
        ax, ay, bx, by = x1 - x0, y1 - y0, x2 - x1, y2 - y1
        la, lb = (ax * ax + ay * ay) ** 0.5, (bx * bx + by * by) ** 0.5
        if la == 0.0 or lb == 0.0 or ax * by - ay * bx < -SIN_TOL * la * lb:
            return False
    return True


def remove_slivers(mesh, spec, polys, joints) -> dict:
    """Apply the sliver control above to ``mesh`` in place; returns counts and what is left."""
    names = [r.name for r in spec.regions]
    vor = {i: spec.voronoi[n] for i, n in enumerate(names) if n in spec.voronoi}
    log = {"merged_blocks": 0, "collapsed_edges": 0, "vanished_blocks": 0}
    if not vor:
        return log
    area, cen = mesh.area_centroid()
    h = np.full(len(mesh.blocks), np.nan)
    for ri, vs in vor.items():
        m = np.asarray(mesh.region) == ri
        if m.any():
            h[m] = vs.local_size(cen[m])
    inc = defaultdict(set)
    for b, loop in enumerate(mesh.blocks):
        for v in loop:
            inc[v].add(b)
    cons = _Constraints(polys, joints, mesh.tol)
    ctx = dict(mesh=mesh, inc=inc, cons=cons, vor=vor, h=h, cls={})
    log["merged_blocks"] = _merge_small_blocks(ctx, area)
    log["collapsed_edges"], log["vanished_blocks"] = _collapse_short_edges(ctx)
    _drop_straight_private_vertices(ctx)
    keep = [b for b, loop in enumerate(mesh.blocks) if loop is not None]
    mesh.blocks = [mesh.blocks[b] for b in keep]
    mesh.region = [mesh.region[b] for b in keep]
    return log


def _merge_small_blocks(ctx, area) -> int:
    mesh, inc, cons, vor, h = ctx["mesh"], ctx["inc"], ctx["cons"], ctx["vor"], ctx["h"]
    n = 0
    frac = np.array([vor[r].min_area_fraction if r in vor else np.nan for r in mesh.region])
    small = np.nonzero(area < frac * h ** 2)[0]
    for b in small[np.argsort(area[small], kind="stable")]:
        ri = mesh.region[b]
        if ri not in vor or mesh.blocks[b] is None:
            continue
        loop = mesh.blocks[b]
        cands = []
        for i, u in enumerate(loop):
            v = loop[(i + 1) % len(loop)]
            mid = 0.5 * (mesh.X[u] + mesh.X[v])
            if cons.on(mid):
                continue  # a boundary or joint edge: never merge across it
            for nb in (inc[u] & inc[v]) - {b}:
                if mesh.region[nb] == ri:
                    cands.append((-np.hypot(*(mesh.X[u] - mesh.X[v])), nb, u, v))
        for _, nb, u, v in sorted(cands):
            union = _merge_loops(loop, mesh.blocks[nb], u, v)
            if union is None or not _convex(mesh.X[union]):
                continue
            mesh.blocks[nb] = union
            mesh.blocks[b] = None
            for w in loop:
                inc[w].discard(b)
                inc[w].add(nb)
            n += 1
            break
    return n


def _vertex_class(ctx, v):
    """('fixed', segs), ('line', segs) or ('free', set())."""
    cls = ctx["cls"]
    if v not in cls:
        mesh, cons = ctx["mesh"], ctx["cons"]
        segs = cons.on(mesh.X[v])
        if any(mesh.region[b] not in ctx["vor"] for b in ctx["inc"][v]):
            cls[v] = ("fixed", segs)
        elif not segs:
            cls[v] = ("free", segs)
        elif cons.is_end(mesh.X[v], segs) or not _straight_pair(segs, segs, cons):
            cls[v] = ("fixed", segs)
        else:
            cls[v] = ("line", segs)
    return ctx["cls"][v]


def _collapse_target(ctx, u, v):
    """(keep, drop, new position) for collapsing edge u-v, or None if not allowed."""
    X = ctx["mesh"].X
    (cu, su), (cv, sv) = _vertex_class(ctx, u), _vertex_class(ctx, v)
    if cu == "free" and cv == "free":
        return u, v, 0.5 * (X[u] + X[v])
    if cu == "free":
        return v, u, X[v].copy()
    if cv == "free":
        return u, v, X[u].copy()
    if cu == "line" and cv == "line" and su & sv and _straight_pair(su, sv, ctx["cons"]):
        return u, v, 0.5 * (X[u] + X[v])
    if cu == "fixed" and cv == "line" and sv <= su:
        return u, v, X[u].copy()
    if cv == "fixed" and cu == "line" and su <= sv:
        return v, u, X[v].copy()
    return None


def _collapse_short_edges(ctx) -> tuple:
    mesh, inc, vor, h = ctx["mesh"], ctx["inc"], ctx["vor"], ctx["h"]
    ids, off, alive = mesh_csr(mesh)
    owner = alive[np.repeat(np.arange(len(off) - 1), np.diff(off))]
    nxt = np.arange(len(ids)) + 1
    nxt[off[1:] - 1] = off[:-1]
    ln = np.hypot(*(mesh.X[ids[nxt]] - mesh.X[ids]).T)
    frac = np.array([vor[r].min_edge_fraction if r in vor else np.nan for r in mesh.region])
    lim = (frac * h)[owner]
    hit = np.nonzero(ln < lim)[0]  # NaN limits (non-Voronoi blocks) never hit
    short = {}
    for i in hit[np.argsort(ln[hit], kind="stable")]:
        u, v = int(ids[i]), int(ids[nxt[i]])
        key = (min(u, v), max(u, v))
        short[key] = max(short.get(key, 0.0), lim[i])
    n_collapsed = n_vanished = 0
    for (u, v), lim in short.items():  # shortest first
        if not (inc[u] & inc[v]) or np.hypot(*(mesh.X[u] - mesh.X[v])) >= lim:
            continue
        tgt = _collapse_target(ctx, u, v)
        if tgt is None:
            continue
        keep, drop, p = tgt
        touched = inc[u] | inc[v]
        old = mesh.X[keep].copy()
        mesh.X[keep] = p
        new, ok = {}, True
        for b in touched:
            loop = _dedupe([keep if w == drop else w for w in mesh.blocks[b]])
            if len(loop) >= 3 and len(set(loop)) != len(loop):
                ok = False
                break
            if len(loop) < 3:  # a triangle whose collapsing edge was its own: it vanishes
                new[b] = None
            # a block flattened onto a line by a moved vertex may not vanish: its remaining
            # vertices would be left as T-junctions on its neighbours' edges
            elif _area(mesh.X[loop]) <= mesh.tol * np.sqrt(abs(_area(mesh.X[mesh.blocks[b]]))) \
                    or not _convex(mesh.X[loop]):
                ok = False
                break
            else:
                new[b] = loop
        if not ok or all(nl is None for nl in new.values()):
            mesh.X[keep] = old
            continue
        for b, loop in new.items():
            if loop is None:
                for w in mesh.blocks[b]:
                    inc[w].discard(b)
                mesh.blocks[b] = None
                n_vanished += 1
            else:
                mesh.blocks[b] = loop
        inc[keep] |= {b for b in inc[drop] if mesh.blocks[b] is not None}
        inc[keep] = {b for b in inc[keep] if mesh.blocks[b] is not None}
        inc[drop] = set()
        n_collapsed += 1
    return n_collapsed, n_vanished


def _drop_straight_private_vertices(ctx) -> None:
    """Remove 180-degree vertices that no other block uses (they carry no contact)."""
    mesh, inc = ctx["mesh"], ctx["inc"]
    ids, off, alive = mesh_csr(mesh)
    if len(ids) == 0:
        return
    owner = np.repeat(np.arange(len(off) - 1), np.diff(off))
    nxt = np.arange(len(ids)) + 1
    nxt[off[1:] - 1] = off[:-1]
    prv = np.empty_like(nxt)
    prv[nxt] = np.arange(len(ids))
    e, ep = mesh.X[ids[nxt]] - mesh.X[ids], mesh.X[ids] - mesh.X[ids[prv]]
    cross = ep[:, 0] * e[:, 1] - ep[:, 1] * e[:, 0]
    straight = np.abs(cross) <= 1e-12 * np.hypot(*e.T) * np.hypot(*ep.T)
    for k in np.unique(owner[straight]):
        b = int(alive[k])
        loop = mesh.blocks[b]
        cand = ids[off[k]:off[k + 1]][straight[off[k]:off[k + 1]]]
        drop = [int(v) for v in cand if inc[int(v)] <= {b}]
        if drop and len(loop) - len(drop) >= 3:
            mesh.blocks[b] = [w for w in loop if w not in drop]


def mesh_csr(mesh):
    """CSR (ids, offsets) of the blocks still alive (None entries skipped)."""
    alive_idx = [b for b, loop in enumerate(mesh.blocks) if loop is not None]
    alive = [mesh.blocks[b] for b in alive_idx]
    lens = np.fromiter((len(b) for b in alive), np.int64, len(alive))
    ids = np.fromiter((v for b in alive for v in b), np.int64, int(lens.sum()))
    return ids, np.r_[0, np.cumsum(lens)].astype(np.int64), np.asarray(alive_idx, np.int64)
