"""Matplotlib picture of a model: deformed blocks, coloured by displacement, and the cracks."""
from __future__ import annotations

import numpy as np

from .detection import world_vertices

__all__ = ["plot_model"]


def plot_model(model, ax=None, displacement_scale=1.0, cracks=True, support=True):
    """Draw the active blocks (displacements magnified by ``displacement_scale``), the crack
    log (tension red, shear blue) and the support (cables and liners coloured by their axial
    force, broken parts dashed) on ``ax``; returns the axes."""
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    if ax is None:
        _, ax = plt.subplots(figsize=(7, 6))
    p, s = model.props, model.state
    pos = s.pos0 + displacement_scale * (s.pos - s.pos0)
    theta = displacement_scale * s.theta
    rot = np.column_stack([np.cos(theta), np.sin(theta)])
    wv = world_vertices(pos, rot, p.vertex_offsets, p.local_vertices)
    off = p.vertex_offsets
    act = np.flatnonzero(p.active > 0)
    polys = [wv[off[b]:off[b + 1]] for b in act]
    u = np.hypot(*(s.pos - s.pos0)[act].T)
    pc = PolyCollection(polys, array=u, cmap="viridis", edgecolors="0.6", linewidths=0.2)
    ax.add_collection(pc)
    plt.colorbar(pc, ax=ax, label="displacement (m)")
    if support and (model.cables.seg_a.size or model.liners.el_a.size):
        _draw_support(model, ax, pos, rot, displacement_scale)
    if cracks:
        log = model.crack_log()
        for mode, colour, label in ((1, "red", "tension"), (2, "blue", "shear")):
            k = log["mode"] == mode
            if k.any():
                ax.plot(log["x"][k], log["y"][k], ".", ms=3, color=colour, label=label)
    if ax.get_legend_handles_labels()[1]:
        ax.legend(loc="upper right")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    return ax


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
