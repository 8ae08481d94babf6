"""Matplotlib pictures of a model: deformed blocks coloured by displacement, joints, cracks,
the rupture surface and the support.

``block_picture(model)`` takes what a picture needs as plain arrays (so a sweep member running
in another process can return it, and a kept result can be drawn later); ``draw_picture`` draws
it with the displacement magnified; ``plot_model`` does both for a model at hand and adds the
support. Crack segments are the shared edges whose bond broke (the first break of each edge
gives its mode), drawn with the block on their A side, so a crack stays on the blocks however
far they moved; the rupture polyline (``dem_core.output.rupture``) is drawn where it formed, in the
undeformed slope.
"""
from __future__ import annotations

import numpy as np

from ..contact.broad import world_vertices

__all__ = ["plot_model", "block_picture", "draw_picture", "magnification"]

JOINT, TENSION, SHEAR = 0, 1, 2          # segment kinds of a picture (crack modes 1, 2)


def plot_model(model, ax=None, displacement_scale=1.0, cracks=True, support=True,
               crack_lines=False, joints=None, rupture=None, crack_materials=None, unit="m",
               colour_limit=None):
    """Draw the active blocks (displacements magnified by ``displacement_scale``, coloured by
    the true displacement), the cracks (tension red, shear blue) and the support (cables and
    liners coloured by their axial force, broken parts dashed) on ``ax``; returns the axes.

    ``cracks``: draw the cracks at all; as the crack log's points (where each bond broke), or
    with ``crack_lines=True`` as segments along the broken bonds' edges, moving with the blocks.
    ``joints``: a material-name prefix (or tuple of them), e.g. "joint:", whose shared edges are
    drawn as thin dark lines. ``rupture``: (n, 2) polyline, m, drawn thick black.
    ``crack_materials``: with ``crack_lines``, draw only the broken bonds of materials whose
    names start with these prefixes (e.g. ("flaw:", "boundary:"): the intact rock's); None: all.
    ``unit``, ``colour_limit``: of the displacement colours, as ``draw_picture``'s.
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(7, 6))
    pic = block_picture(model, cracks=crack_materials if (cracks and crack_lines) else (),
                        joints=() if joints is None else joints)
    draw_picture(pic, ax, displacement_scale, rupture=rupture, unit=unit,
                 colour_limit=colour_limit)
    s = model.state
    pos = s.pos0 + displacement_scale * (s.pos - s.pos0)
    theta = s.theta0 + displacement_scale * (s.theta - s.theta0)
    rot = np.column_stack([np.cos(theta), np.sin(theta)])
    if support and (model.cables.seg_a.size or model.liners.el_a.size):
        _draw_support(model, ax, pos, rot, displacement_scale)
    if cracks and not crack_lines:
        log = model.crack_log()
        for mode, colour, label in ((1, "red", "tension"), (2, "blue", "shear")):
            k = log["mode"] == mode
            if k.any():
                ax.plot(log["x"][k], log["y"][k], ".", ms=3, color=colour, label=label)
    if ax.get_legend_handles_labels()[1]:
        ax.legend(loc="upper right")
    ax.autoscale_view()
    return ax


def block_picture(model, cracks=None, joints="joint:") -> dict:
    """What a picture of the model needs, as plain arrays (nb blocks, ns segments):

    ``offsets`` (nb + 1,), ``local`` (nv, 2) m: the blocks' vertices in their own frames
    (``BlockProps``); ``pos0``, ``pos`` (nb, 2) m and ``theta0``, ``theta`` (nb,) rad: the
    start and present poses; ``active`` (nb,) int8; ``segment_block`` (ns,) and
    ``segment_local`` (ns, 2, 2) m: shared edges in the frame of their block A;
    ``segment_kind`` (ns,): ``JOINT``, ``TENSION`` or ``SHEAR``.

    ``cracks``: material-name prefixes (str or tuple) of the broken bonds to draw, None for
    all, () for none; ``joints``: prefixes of the joint edges to draw (() for none).
    """
    p, s, bs = model.props, model.state, model.blocks
    joints = _prefixes(joints)
    joint_edges = np.flatnonzero([bool(joints) and bs.material_names[m].startswith(joints)
                                  for m in bs.edge_material]).astype(np.int64)
    crack_edges, modes = _broken_edges(model, cracks)
    edges = np.concatenate([joint_edges, crack_edges]).astype(np.int64)
    kind = np.concatenate([np.full(joint_edges.size, JOINT), modes]).astype(np.int8)
    a = bs.edge_block_a[edges].astype(np.int64)
    ends = np.stack([bs.edge_p0[edges], bs.edge_p1[edges]], axis=1) - s.pos0[a][:, None, :]
    cos_t, sin_t = np.cos(s.theta0[a])[:, None], np.sin(s.theta0[a])[:, None]
    local = np.stack([cos_t * ends[..., 0] + sin_t * ends[..., 1],
                      -sin_t * ends[..., 0] + cos_t * ends[..., 1]], axis=-1)
    return {"offsets": p.vertex_offsets.copy(), "local": p.local_vertices.copy(),
            "pos0": s.pos0.copy(), "pos": s.pos.copy(), "theta0": s.theta0.copy(),
            "theta": s.theta.copy(), "active": p.active.copy(), "segment_block": a,
            "segment_local": local.reshape(-1, 2, 2), "segment_kind": kind}


def _broken_edges(model, prefixes):
    """Shared edges (indices) whose bond broke, of materials starting with ``prefixes`` (None:
    any), and the mode of each edge's first break (1 tension, 2 shear)."""
    none = np.zeros(0, np.int64), np.zeros(0, np.int8)
    bs, prefixes = model.blocks, _prefixes(prefixes)
    if prefixes == () or not bs.n_edges:
        return none
    log = model.crack_log()
    keep = np.array([prefixes is None or m.startswith(prefixes) for m in log["material"]],
                    bool)
    if not keep.any():
        return none
    nb = np.int64(bs.n_blocks)
    ea, eb = bs.edge_block_a.astype(np.int64), bs.edge_block_b.astype(np.int64)
    order = np.argsort(np.minimum(ea, eb) * nb + np.maximum(ea, eb), kind="stable")
    keys = (np.minimum(ea, eb) * nb + np.maximum(ea, eb))[order]
    a, b = log["block_a"][keep], log["block_b"][keep]
    want = np.minimum(a, b) * nb + np.maximum(a, b)
    j = np.minimum(np.searchsorted(keys, want), keys.size - 1)
    found = keys[j] == want
    edge, first = np.unique(order[j[found]], return_index=True)    # first break: time order
    return edge, log["mode"][keep][found][first].astype(np.int8)


def _prefixes(names):
    """None, or a tuple of material-name prefixes from a str or a sequence."""
    return None if names is None else (names,) if isinstance(names, str) else tuple(names)


def magnification(pic, fraction=0.05) -> float:
    """A displacement magnification (1, 2, 5, 10, 20, ...; at least 1) that draws the largest
    block displacement of ``pic`` at about ``fraction`` of the model's size."""
    u = np.hypot(*(np.asarray(pic["pos"]) - np.asarray(pic["pos0"])).T)
    act = (np.asarray(pic["active"]) > 0) & np.isfinite(u)
    u, xy = u[act], np.asarray(pic["pos0"])[act]
    size = float(np.ptp(xy, axis=0).max()) if len(xy) else 0.0
    if not len(u) or u.max() <= 0 or size <= 0:
        return 1.0
    k = fraction * size / u.max()
    if k <= 1:
        return 1.0
    decade = 10.0 ** np.floor(np.log10(k))
    return float(max(f for f in (1, 2, 5) if f * decade <= k) * decade)


def draw_picture(pic, ax, displacement_scale=1.0, rupture=None, unit="m", colour_limit=None):
    """Draw a ``block_picture`` on ``ax``: the active blocks at their start pose plus
    ``displacement_scale`` times their motion, coloured by the true centroid displacement (in
    ``unit``, "m" or "mm"; capped at ``colour_limit`` in that unit, if given; a colour bar is
    added), joints as thin dark lines, cracks as red (tension) and blue (shear) segments, the
    ``rupture`` polyline (m) thick black. Blocks whose pose is not finite (a model that blew
    up) are left out. Returns the block collection."""
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection, PolyCollection

    k = float(displacement_scale)
    pos0, pos = np.asarray(pic["pos0"]), np.asarray(pic["pos"])
    theta0, theta = np.asarray(pic["theta0"]), np.asarray(pic["theta"])
    at, th = pos0 + k * (pos - pos0), theta0 + k * (theta - theta0)
    off, lv = np.asarray(pic["offsets"]), np.asarray(pic["local"], float)
    wv = world_vertices(at, np.column_stack([np.cos(th), np.sin(th)]), off, lv)
    act = np.flatnonzero((np.asarray(pic["active"]) > 0) & np.isfinite(at).all(axis=1)
                         & np.isfinite(th))            # a blown-up block is left out
    scale = {"m": 1.0, "mm": 1e3}[unit]
    u = scale * np.hypot(*(pos - pos0)[act].T)
    pc = PolyCollection([wv[off[b]:off[b + 1]] for b in act], array=u, cmap="viridis",
                        edgecolors="0.6", linewidths=0.2)
    if colour_limit is not None:
        pc.set_clim(0.0, colour_limit)
    ax.add_collection(pc)
    plt.colorbar(pc, ax=ax, label=f"displacement ({unit})",
                 extend="max" if colour_limit is not None and u.max(initial=0) > colour_limit
                 else "neither")
    blk = np.asarray(pic["segment_block"], np.int64)
    seg = np.asarray(pic["segment_local"], float).reshape(-1, 2, 2)
    kind = np.asarray(pic["segment_kind"])
    shown = np.isin(blk, act)
    cos_t, sin_t = np.cos(th[blk])[:, None], np.sin(th[blk])[:, None]
    world = at[blk][:, None, :] + np.stack([cos_t * seg[..., 0] - sin_t * seg[..., 1],
                                            sin_t * seg[..., 0] + cos_t * seg[..., 1]], axis=-1)
    for kd, colour, width, label in ((JOINT, "k", 0.9, "joints"),
                                     (TENSION, "red", 1.6, "cracks, tension"),
                                     (SHEAR, "blue", 1.6, "cracks, shear")):
        sel = shown & (kind == kd)
        if sel.any():
            ax.add_collection(LineCollection(world[sel], colors=colour, linewidths=width,
                                             label=label))
    if rupture is not None and len(rupture):
        line = np.asarray(rupture, float)
        ax.plot(line[:, 0], line[:, 1], "k-", lw=2.5, label="rupture surface")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    return pc


def _shown(model, host, local, xy, xy0, pos, rot, scale):
    """Support nodes as drawn: a held node at its host point's drawn place plus its magnified
    offset from it; a free node (its host excavated) at its installed place plus its magnified
    displacement since."""
    out = xy0 + scale * (xy - xy0)
    ok = (host >= 0) & (model.props.active[np.maximum(host, 0)] > 0)
    h, r = host[ok], local[ok]
    s = model.state
    now = s.pos[h] + np.column_stack([s.rot[h, 0] * r[:, 0] - s.rot[h, 1] * r[:, 1],
                                      s.rot[h, 1] * r[:, 0] + s.rot[h, 0] * r[:, 1]])
    drawn = pos[h] + np.column_stack([rot[h, 0] * r[:, 0] - rot[h, 1] * r[:, 1],
                                      rot[h, 1] * r[:, 0] + rot[h, 0] * r[:, 1]])
    out[ok] = drawn + scale * (xy[ok] - now)
    return out


def _draw_support(model, ax, pos, rot, scale):
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    cb, ln = model.cables, model.liners
    first = np.zeros(ln.node_pos.shape[0], np.int64) - 1
    first[ln.bond_node[::-1]] = ln.bond_host[::-1]
    local = np.zeros_like(ln.node_pos)
    local[ln.bond_node[::-1]] = ln.bond_local[::-1]
    xc = _shown(model, cb.node_host, cb.node_local, cb.node_pos, cb.node_pos0, pos, rot, scale)
    xl = _shown(model, first, local, ln.node_pos, ln.node_pos0, pos, rot, scale)
    segs = [np.stack([xc[cb.seg_a], xc[cb.seg_b]], axis=1),
            np.stack([xl[ln.el_a], xl[ln.el_b]], axis=1)]
    force = np.concatenate([cb.seg_force, ln.el_force[:, 0]]) / 1e3
    width = np.concatenate([np.full(cb.seg_a.size, 1.5), np.full(ln.el_a.size, 3.0)])
    broken = np.concatenate([cb.seg_state == 2, np.zeros(ln.el_a.size, bool)])
    lines = np.concatenate(segs)
    top = float(np.abs(force).max()) or 1.0
    lc = LineCollection(lines[~broken], array=force[~broken], cmap="coolwarm", clim=(-top, top),
                        linewidths=width[~broken])
    ax.add_collection(lc)
    plt.colorbar(lc, ax=ax, label="support axial force (kN/m, tension +)",
                 orientation="horizontal", fraction=0.05, pad=0.15)
    if broken.any():
        ax.add_collection(LineCollection(lines[broken], colors="k", linestyles=":",
                                         linewidths=2.0, label="ruptured cable"))
