"""Support: grouted cables and rock bolts, and shotcrete liners, as records a scene installs.

    model.install(Cable(collar=(2.0, 5.0), end=(8.0, 3.0), area=625e-6, E=98e9,
                        yield_tension=0.548e6, grout_stiffness=6e9, grout_strength=0.32e6,
                        spacing=8.0))
    model.install(Liner("face", thickness=0.15, E=25e9, tensile_yield=3e6,
                        compressive_yield=35e6, bond_kn=5e9, bond_ks=2e9,
                        bond_tension=0.5e6, bond_shear=1e6))

Both are also stage records (kinds "cable" and "liner"): installed at that point of a staged
run, stress-free in the pose the model has then. A rock bolt is a short ``Cable``; ``plate``
holds its collar to the rock (a face plate) and ``free_length`` leaves the part next to the
collar ungrouted (the free length a ``pretension`` acts on). The mechanics and the symbols are
in ``components/cables.py`` and ``components/liner.py``; units SI, forces of a cable per cable
(N), divided by ``spacing`` (m, out of plane) inside. Reference: Itasca UDEC manual, structural
elements (cable, liner); Farmer (1975) for the grouted bar's axial force decay.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
import shapely

from .cables import GROUT_SLIP, LINER_BOND, RUPTURE, YIELD, Cables, no_cables
from .liner import no_liners

__all__ = ["Cable", "Liner", "installed", "has_nodes", "support_stiffness", "set_node_masses",
           "support_log", "no_cables", "no_liners", "decay_length", "check_in_rock",
           "liner_faces"]


def _positive(where, **values):
    for k, v in values.items():
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ValueError(f"{where}: {k} must be a finite number > 0, got {v!r}")


def _not_negative(where, **values):
    for k, v in values.items():
        if not (isinstance(v, (int, float)) and v >= 0 and not math.isnan(v)):
            raise ValueError(f"{where}: {k} must be >= 0, got {v!r}")


@dataclass(frozen=True)
class Cable:
    """A grouted cable or bolt from ``collar`` to ``end`` ((x, y) m, both in rock; one that
    lies in a gap at installation moves along the cable into rock, ``_into_rock``).

    area (m^2), E (Pa): the steel; yield_tension, yield_compression (N, default the tension
    value): axial yield forces; rupture_strain: total strain at which a segment breaks;
    grout_stiffness (N/m per m of cable), grout_strength (N/m: force per metre of bond);
    spacing (m): out-of-plane spacing of the cables this one stands for; segment_length (m,
    default the median block radius); free_length (m from the collar, ungrouted); plate: a face
    plate holds the collar node to its block (a spring ten times a segment's axial stiffness,
    no slip); pretension (N, needs a plate and a free length): the locked-off force, i.e. the
    free length is stretched by what it takes to hold this force once the grouted anchor
    (elastic draw-in s / sqrt(E A k_g)) and the plate have taken it up.
    """

    collar: tuple
    end: tuple
    area: float
    E: float
    yield_tension: float
    grout_stiffness: float
    grout_strength: float
    yield_compression: float | None = None
    rupture_strain: float = 0.1
    spacing: float = 1.0
    segment_length: float | None = None
    pretension: float = 0.0
    free_length: float = 0.0
    plate: bool = False

    def check(self, i=None, groups=None, materials=None):
        where = "cable" if i is None else f"stage {i} (cable)"
        pts = np.asarray([self.collar, self.end], dtype=np.float64)
        if pts.shape != (2, 2) or not np.all(np.isfinite(pts)):
            raise ValueError(f"{where}: collar and end must be (x, y) points, got "
                             f"{self.collar!r}, {self.end!r}")
        length = float(np.hypot(*(pts[1] - pts[0])))
        if length <= 0:
            raise ValueError(f"{where}: collar and end are the same point {self.collar!r}")
        _positive(where, area=self.area, E=self.E, grout_stiffness=self.grout_stiffness,
                  rupture_strain=self.rupture_strain, spacing=self.spacing)
        _not_negative(where, yield_tension=self.yield_tension, grout_strength=self.grout_strength,
                      pretension=self.pretension, free_length=self.free_length)
        if self.yield_compression is not None:
            _not_negative(where, yield_compression=self.yield_compression)
        if self.segment_length is not None:
            _positive(where, segment_length=self.segment_length)
        if self.free_length >= length:
            raise ValueError(f"{where}: free_length {self.free_length} m must be shorter than "
                             f"the cable ({length:.4g} m)")
        if self.pretension > 0 and (self.free_length == 0 or not self.plate):
            raise ValueError(f"{where}: a pretension needs a free length to act on "
                             "(free_length > 0) and a face plate (plate=True)")
        if self.pretension > self.yield_tension:
            raise ValueError(f"{where}: pretension {self.pretension} N exceeds the yield force "
                             f"{self.yield_tension} N")

    def run(self, model):
        return _install_stage(model, self, "cables", "node_cable")


@dataclass(frozen=True)
class Liner:
    """A shotcrete liner on the exposed faces of the blocks of ``group`` (a named group:
    the surface it covers), optionally only where a face's middle lies inside the polygon
    ``within`` ([[x, y], ...] m). The faces must make one chain.

    thickness (m), E (Pa), density (kg/m^3); tensile_yield, compressive_yield (Pa): the axial
    yield forces are these x thickness; moment_capacity (N m/m, default tensile_yield x
    thickness^2 / 6, the cracking moment); bond_kn, bond_ks (Pa/m), bond_tension, bond_shear
    (Pa): the bond to the rock; segment_length (m, default the median block radius).
    """

    group: str
    thickness: float
    E: float
    tensile_yield: float
    compressive_yield: float
    bond_kn: float
    bond_ks: float
    bond_tension: float
    bond_shear: float
    density: float = 2400.0
    moment_capacity: float | None = None
    segment_length: float | None = None
    within: tuple | None = None

    def check(self, i=None, groups=None, materials=None):
        where = "liner" if i is None else f"stage {i} (liner)"
        if groups is not None and self.group not in groups:
            raise ValueError(f"{where}: no surface (group) named {self.group!r}; groups are "
                             f"{sorted(groups)}")
        _positive(where, thickness=self.thickness, E=self.E, bond_kn=self.bond_kn,
                  bond_ks=self.bond_ks, density=self.density)
        _not_negative(where, tensile_yield=self.tensile_yield,
                      compressive_yield=self.compressive_yield,
                      bond_tension=self.bond_tension, bond_shear=self.bond_shear)
        for k in ("moment_capacity", "segment_length"):
            if getattr(self, k) is not None:
                _positive(where, **{k: getattr(self, k)})
        if self.within is not None:
            w = np.asarray(self.within, dtype=np.float64)
            if w.ndim != 2 or w.shape[1] != 2 or len(w) < 3 or not np.all(np.isfinite(w)):
                raise ValueError(f"{where}: within must be a polygon [[x, y], ...], got "
                                 f"{self.within!r}")

    def run(self, model):
        return _install_stage(model, self, "liners", "node_liner")


def decay_length(area, E, grout_stiffness) -> float:
    """sqrt(E A / k_g), m: the length over which the axial force of an elastic grouted bar
    decays by e (F(x) = F_0 exp(-x / lambda) along a long bar pulled at one end)."""
    return math.sqrt(E * area / grout_stiffness)


# ---------------------------------------------------------------- installing
def _install_stage(model, item, bundle, ids):
    """A "cable" or "liner" stage: install (``Model.install``), report the new element's node
    count."""
    model.install(item)
    element = getattr(getattr(model, bundle), ids)
    return 0, "installed", {"nodes": int((element == element.max()).sum())}


def installed(model, items) -> tuple:
    """(cables, liners): the model's support bundles with a ``Cable`` or ``Liner`` (or a list
    of them: one search of the blocks for all) added in the model's present pose
    (stress-free, except a cable's pretension). The model is only read: ``Model.install``
    keeps the bundles and recomputes the time step."""
    items = list(items) if isinstance(items, (list, tuple)) else [items]
    for item in items:
        if not isinstance(item, (Cable, Liner)):
            raise ValueError(f"install takes Cables and Liners, got {type(item).__name__}")
        item.check(groups=set(model.blocks.groups))
    tree = None
    cables, liners = model.cables, model.liners
    for item in items:
        if isinstance(item, Cable):
            tree = tree or _block_tree(model)
            cables = _join(cables, _cable_arrays(model, item, tree))
        else:
            liners = _join(liners, _liner_arrays(model, item))
    return cables, liners


def _join(bundle, new: dict):
    """``bundle`` with the new element's arrays appended (indices shifted)."""
    node0 = bundle.node_pos.shape[0]
    element = int(bundle.node_cable.max() + 1 if isinstance(bundle, Cables) else
                  bundle.node_liner.max() + 1) if node0 else 0
    n_new = {"node": len(new["node_pos"]), **{k: len(new[f"{k}_{a}"]) for k, a in
                                              (("seg", "a"), ("el", "a"), ("bond", "node"))
                                              if f"{k}_{a}" in new}}
    out = {"log_count": bundle.log_count}
    for f in bundle._fields:
        old = getattr(bundle, f)
        if f in out or f == "log_rows":
            continue
        if f in ("node_cable", "seg_cable", "node_liner", "el_liner"):
            add = np.full(n_new[f.split("_")[0]], element, old.dtype)
        else:
            add = np.asarray(new[f], dtype=old.dtype).reshape((-1,) + old.shape[1:])
        if f in ("seg_a", "seg_b", "el_a", "el_b", "bond_node"):
            add = add + node0
        out[f] = np.concatenate([old, add])
    # each node and segment logs at most twice (slip or bond; yield and rupture)
    cap = max(bundle.log_rows.shape[0], 2 * sum(n_new.values()) + 2 * node0 + 16)
    out["log_rows"] = np.zeros((cap, 7))
    out["log_rows"][:bundle.log_rows.shape[0]] = bundle.log_rows
    return type(bundle)(**out)


def _block_polygons(model):
    p, s = model.props, model.state
    from ..contact.broad import world_vertices
    wv = world_vertices(s.pos, s.rot, p.vertex_offsets, p.local_vertices)
    off = p.vertex_offsets
    act = np.flatnonzero(p.active > 0)
    return act, [shapely.Polygon(wv[off[b]:off[b + 1]]) for b in act]


def _block_tree(model):
    """(active blocks, an R-tree of their polygons in the present pose)."""
    act, polys = _block_polygons(model)
    return act, shapely.STRtree(polys)


def _hosts(tree, pts) -> np.ndarray:
    """The active block containing each point (-1: none), from ``_block_tree``."""
    act, tree = tree
    where = tree.query(shapely.points(pts), predicate="intersects")
    host = np.full(len(pts), -1, np.int64)
    host[where[0][::-1]] = act[where[1][::-1]]          # first hit wins
    return host


def _body(model, host, xy):
    """World points ``xy`` in their host blocks' body frames."""
    s = model.state
    d = xy - s.pos[host]
    cos_t, sin_t = s.rot[host, 0], s.rot[host, 1]
    return np.column_stack([cos_t * d[:, 0] + sin_t * d[:, 1],
                            -sin_t * d[:, 0] + cos_t * d[:, 1]])


# how far along a cable (fraction of its length) a collar or end in a gap moves into rock
REACH_INTO_ROCK = 0.1


def _into_rock(tree, a, b, name):
    """``a`` if it lies in an active block, else the first point from ``a`` towards ``b``
    (sampled every 1/200 of the cable, up to ``REACH_INTO_ROCK`` of it) that does: the hole
    starts where the rock does (a face block that slid away before the installation, a joint
    opened at the collar). The move is reported by a warning; beyond the reach, a ValueError."""
    d = np.linspace(0.0, REACH_INTO_ROCK, int(200 * REACH_INTO_ROCK) + 1)
    pts = a + d[:, None] * (b - a)
    host = _hosts(tree, pts)
    if host[0] >= 0:
        return a
    inside = np.flatnonzero(host >= 0)
    if not len(inside):
        raise ValueError(f"cable: the {name} {tuple(a)} is not inside any active block, nor "
                         f"any point within {REACH_INTO_ROCK:.0%} of the cable from it (a cable "
                         "starts and ends in rock)")
    moved = pts[inside[0]]
    warnings.warn(f"cable: the {name} {tuple(a)} is in a gap between blocks; moved "
                  f"{float(np.hypot(*(moved - a))):.3g} m along the cable into rock, to "
                  f"{tuple(moved)}", stacklevel=4)
    return moved


def check_in_rock(model, cab: Cable) -> None:
    """ValueError (``_into_rock``'s) when the cable's collar or end is not in rock on the
    model as it is: a run checks its cable stages before its first step (``run_stages``)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")         # a point in a gap is moved at installation
        tree = _block_tree(model)
        collar, end = np.asarray(cab.collar, float), np.asarray(cab.end, float)
        _into_rock(tree, collar, end, "collar")
        _into_rock(tree, end, collar, "end")


def _cable_arrays(model, cab: Cable, tree) -> dict:
    collar, end = np.asarray(cab.collar, float), np.asarray(cab.end, float)
    collar, end = _into_rock(tree, collar, end, "collar"), _into_rock(tree, end, collar, "end")
    length = float(np.hypot(*(end - collar)))
    h = cab.segment_length or float(np.median(model.props.radius[model.props.active > 0]))
    nseg = max(2, int(math.ceil(length / h - 1e-9)))
    t = np.linspace(0.0, 1.0, nseg + 1)
    xy = collar + t[:, None] * (end - collar)
    host = _hosts(tree, xy)
    if host[0] < 0 or host[-1] < 0:          # (only by round-off on a block's edge)
        raise ValueError(f"cable: the collar {tuple(xy[0])} or end {tuple(xy[-1])} is not "
                         "inside any active block")
    lseg = length / nseg
    trib = np.full(nseg + 1, lseg)
    trib[[0, -1]] = 0.5 * lseg
    s = cab.spacing
    along = t * length
    free = along < cab.free_length - 1e-9 * length
    cap = np.where(free, 0.0, cab.grout_strength * trib / s)
    grout_k = cab.grout_stiffness * trib / s
    ea = cab.E * cab.area / (lseg * s)
    if cab.plate:
        cap[0], grout_k[0] = np.inf, 10.0 * ea
    local = np.zeros((nseg + 1, 2))
    inside = host >= 0
    local[inside] = _body(model, host[inside], xy[inside])
    seg_free = free[:-1] & (along[1:] <= cab.free_length + 1e-9 * length)
    # lock-off: stretch the free length by what holds the pretension after the anchor's and
    # the plate's draw-in (compliances per unit thickness, m per N/m)
    n_free = max(int(seg_free.sum()), 1)
    draw_in = (n_free / ea + s / math.sqrt(cab.E * cab.area * cab.grout_stiffness)
               + 1.0 / grout_k[0]) * cab.pretension / s
    axis = (end - collar) / length
    yc = cab.yield_tension if cab.yield_compression is None else cab.yield_compression
    return dict(
        node_pos=xy, node_vel=np.zeros((nseg + 1, 2)), node_force=np.zeros((nseg + 1, 2)),
        node_pos0=xy.copy(),
        node_tangent=np.zeros((nseg + 1, 2)), node_axis=np.tile(axis, (nseg + 1, 1)),
        node_host=host, node_local=local, grout_k=grout_k,
        grout_cap=cap, grout_plastic=np.zeros((nseg + 1, 2)), grout_force=np.zeros(nseg + 1),
        node_state=np.zeros(nseg + 1), node_inv_mass=np.zeros(nseg + 1),
        seg_a=np.arange(nseg), seg_b=np.arange(1, nseg + 1), seg_length0=np.full(nseg, lseg),
        seg_k=np.full(nseg, ea), seg_yield_t=np.full(nseg, cab.yield_tension / s),
        seg_yield_c=np.full(nseg, yc / s), seg_rupture=np.full(nseg, cab.rupture_strain),
        seg_plastic=np.where(seg_free, -draw_in / n_free, 0.0),
        seg_force=np.where(seg_free, ea * draw_in / n_free, 0.0), seg_state=np.zeros(nseg))


def liner_faces(blocks, active, members, ln: Liner) -> list:
    """The exposed faces a liner on blocks ``members`` covers, in order along their one chain:
    [(block, p0, p1)], p0, p1 (2,) in the block's body frame, with the blocks ``active``
    (nb,) left (``water.exposed_faces``; a face only by its edges, not by where the blocks
    have moved). ValueError when there is no exposed face (every edge of the group's blocks is
    shared with another active block, or none lies ``within``) or they make no one chain."""
    from .water import exposed_faces
    fb, f0, f1 = exposed_faces(blocks, active)
    mine = np.isin(fb, members)
    if ln.within is not None:
        mid = 0.5 * (f0 + f1) + blocks.centroid[fb]
        inside = shapely.contains_xy(shapely.Polygon(np.asarray(ln.within, float)),
                                     mid[:, 0], mid[:, 1])
        mine &= inside
    if not mine.any():
        left = int(np.count_nonzero(np.asarray(active)[members]))
        why = (" inside `within` (no exposed face's middle lies in that polygon)"
               if ln.within is not None and np.isin(fb, members).any() else
               f" ({left} of its {len(members)} blocks left, each edge shared with another "
               "block): give the group of the blocks on the surface, or excavate before the "
               "liner")
        raise ValueError(f"liner: group {ln.group!r} has no exposed face{why}")
    return _chain(fb[mine], f0[mine], f1[mine], blocks.centroid, ln.group)


def _liner_arrays(model, ln: Liner) -> dict:
    blocks = model.blocks
    chain = liner_faces(blocks, model.props.active, model.group(ln.group), ln)
    h = ln.segment_length or float(np.median(model.props.radius[model.props.active > 0]))
    st = model.state
    nodes, bonds = [], []                 # bonds: (node, block, normal, length)
    for b, p0, p1 in chain:
        d = p1 - p0
        flen = float(np.hypot(*d))
        k = max(1, int(math.ceil(flen / h - 1e-9)))
        ends = [p0 + j / k * d for j in range(k + 1)]     # body frame of b
        world = [st.pos[b] + _rotate(st.rot[b], e) for e in ends]
        if not nodes:
            nodes.append(world[0])
        for j in range(k):
            nodes.append(world[j + 1])
            for node in (len(nodes) - 2, len(nodes) - 1):
                bonds.append((node, b, np.array([d[1], -d[0]]) / flen, 0.5 * flen / k))
    xy = np.asarray(nodes)
    n = len(xy)
    bn = np.array([r[0] for r in bonds], np.int64)
    host = np.array([r[1] for r in bonds], np.int64)
    # each bond holds its node where it was sprayed: where two blocks' faces meet at a node,
    # the blocks may have moved apart before the liner went on, and the node sits at the first
    # face's end, so the second block's body point is taken under the node, not at its corner
    # (a bond stretched at installation would push the blocks apart)
    local = _body(model, host, xy[bn])
    blen = np.array([r[3] for r in bonds])
    mass = np.zeros(n)
    np.add.at(mass, bn, ln.density * ln.thickness * blen)
    d = np.diff(xy, axis=0)
    t = ln.thickness
    mp = ln.moment_capacity if ln.moment_capacity is not None else ln.tensile_yield * t * t / 6
    return dict(
        node_pos=xy, node_theta=np.zeros(n), node_vel=np.zeros((n, 2)), node_omega=np.zeros(n),
        node_force=np.zeros((n, 3)), node_pos0=xy.copy(), node_mass=mass, node_inv_mass=np.zeros(n),
        node_inv_inertia=np.zeros(n),
        bond_node=bn, bond_host=host, bond_local=local,
        bond_normal=np.array([r[2] for r in bonds]), bond_theta0=st.theta[host],
        bond_length=blen, bond_kn=ln.bond_kn * blen, bond_ks=ln.bond_ks * blen,
        bond_kr=ln.bond_kn * blen ** 3 / 3.0, bond_tension=np.full(len(bn), ln.bond_tension),
        bond_shear=np.full(len(bn), ln.bond_shear), bond_state=np.zeros(len(bn)),
        bond_force=np.zeros((len(bn), 3)),
        el_a=np.arange(n - 1), el_b=np.arange(1, n), el_length0=np.hypot(d[:, 0], d[:, 1]),
        el_angle0=np.arctan2(d[:, 1], d[:, 0]), el_ea=np.full(n - 1, ln.E * t),
        el_ei=np.full(n - 1, ln.E * t ** 3 / 12.0), el_nt=np.full(n - 1, ln.tensile_yield * t),
        el_nc=np.full(n - 1, ln.compressive_yield * t), el_mp=np.full(n - 1, mp),
        el_plastic=np.zeros((n - 1, 3)), el_force=np.zeros((n - 1, 3)), el_state=np.zeros(n - 1))


def _rotate(rot, v):
    return np.array([rot[0] * v[0] - rot[1] * v[1], rot[1] * v[0] + rot[0] * v[1]])


def _chain(fb, f0, f1, centroid, group):
    """The faces (block, p0, p1 in body frame) in order along one chain (faces of one block
    run counter-clockwise, so along a free surface one face's end is the next one's start)."""
    w0, w1 = f0 + centroid[fb], f1 + centroid[fb]
    scale = float(np.ptp(np.vstack([w0, w1]), axis=0).max()) or 1.0
    key = lambda p: tuple(np.round(p / (1e-7 * scale)).astype(np.int64))  # noqa: E731
    starts = {key(p): i for i, p in enumerate(w0)}
    nxt = np.array([starts.get(key(p), -1) for p in w1])
    has_prev = np.zeros(len(fb), bool)
    has_prev[nxt[nxt >= 0]] = True
    heads = np.flatnonzero(~has_prev)
    if len(heads) != 1:
        raise ValueError(f"liner on {group!r}: its exposed faces make "
                         f"{max(len(heads), 1) if len(heads) else 'a closed loop of'} separate "
                         "chains; pick one stretch of surface with `within`")
    order, i = [], int(heads[0])
    while i >= 0 and len(order) < len(fb):
        order.append(i)
        i = int(nxt[i])
    if len(order) != len(fb):
        raise ValueError(f"liner on {group!r}: its exposed faces do not make one chain; pick "
                         "one stretch of surface with `within`")
    return [(int(fb[i]), f0[i], f1[i]) for i in order]


# ---------------------------------------------------------------- time step
def has_nodes(cb, ln) -> bool:
    """Whether there is any cable (``cb``, a Cables bundle) or liner (``ln``, Liners)."""
    return cb.node_pos.shape[0] + ln.node_pos.shape[0] > 0


def support_stiffness(cb, ln, nb):
    """(kt, kr) per block (``nb`` blocks), N/m and N m: the grout and bond springs of the
    cables ``cb`` and liners ``ln`` acting on each block, for the blocks' frequency bound
    (``step.run.frequency_bound``: omega^2 <= 2 (kt/m + kr/I))."""
    kt, kr = np.zeros(nb), np.zeros(nb)
    for host, local, k, k_turn in ((cb.node_host, cb.node_local, 2.0 * cb.grout_k, 0.0),
                                   (ln.bond_host, ln.bond_local, ln.bond_kn + ln.bond_ks,
                                    ln.bond_kr)):
        ok = host >= 0
        np.add.at(kt, host[ok], k[ok])
        np.add.at(kr, host[ok], (k * (local ** 2).sum(axis=1) + 2.0 * k_turn)[ok])
    return kt, kr


def set_node_masses(cb, ln, w2max: float):
    """Inertial masses of the support nodes: each node's Gershgorin bound 2 k / m equals the
    blocks' largest omega^2 (``w2max``), so the nodes never set the time step. A liner node's
    moment of inertia is m l^2 (l its shorter element), which bounds its rotation the same
    way."""
    if cb.node_pos.shape[0]:
        k = 2.0 * cb.grout_k.copy()
        np.add.at(k, cb.seg_a, 3.0 * cb.seg_k)
        np.add.at(k, cb.seg_b, 3.0 * cb.seg_k)
        cb.node_inv_mass[:] = w2max / (2.0 * k)
    if ln.node_pos.shape[0]:
        nn = ln.node_pos.shape[0]
        kel = 2.0 * ln.el_ea / ln.el_length0 + 36.0 * ln.el_ei / ln.el_length0 ** 3
        k, k_turn = np.zeros(nn), np.zeros(nn)
        np.add.at(k, ln.bond_node, ln.bond_kn + ln.bond_ks)
        np.add.at(k_turn, ln.bond_node, 2.0 * ln.bond_kr)
        np.add.at(k, ln.el_a, kel)
        np.add.at(k, ln.el_b, kel)
        lmin = np.full(nn, np.inf)
        np.minimum.at(lmin, ln.el_a, ln.el_length0)
        np.minimum.at(lmin, ln.el_b, ln.el_length0)
        mass = np.maximum(2.0 * k / w2max, ln.node_mass)
        inertia = mass * lmin ** 2 + 2.0 * k_turn / w2max
        ln.node_inv_mass[:] = 1.0 / mass
        ln.node_inv_inertia[:] = 1.0 / inertia


def unbalanced(cb, ln, gravity):
    """(sum |unbalanced force|, sum of the forces acting) over the support nodes, N/m: their
    part of the model's unbalanced ratio (``monitor.unbalanced_ratio``)."""
    num = float(np.hypot(*cb.node_force.T).sum()) + float(np.hypot(*ln.node_force[:, :2].T).sum())
    shear = np.abs(ln.el_force[:, 1] + ln.el_force[:, 2]) / ln.el_length0
    den = (2.0 * float(np.abs(cb.seg_force).sum()) + float(np.abs(cb.grout_force).sum())
           + 2.0 * float((np.abs(ln.el_force[:, 0]) + shear).sum())
           + float(np.hypot(*ln.bond_force[:, :2].T).sum())
           + float(ln.node_mass.sum()) * float(np.hypot(*gravity)))
    return num, den


# ---------------------------------------------------------------- results
_KINDS = {GROUT_SLIP: "grout slip", YIELD: "yield", RUPTURE: "rupture",
          LINER_BOND: "bond failure"}


def support_log(model) -> dict:
    """Support events so far: time (s), x, y (m), kind ("grout slip", "yield", "rupture",
    "bond failure"), element ("cable i" / "liner i") and part (node or segment index)."""
    out = {"time": [], "x": [], "y": [], "kind": [], "element": [], "part": []}
    for what, b in (("cable", model.cables), ("liner", model.liners)):
        n = min(int(b.log_count[0]), b.log_rows.shape[0])
        for r in b.log_rows[:n]:
            out["time"].append(r[0])
            out["x"].append(r[1])
            out["y"].append(r[2])
            out["kind"].append(_KINDS[int(r[3])])
            out["element"].append(f"{what} {int(r[4])}")
            out["part"].append(int(r[5]))
    return out
