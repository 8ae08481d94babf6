"""Matplotlib picture of a model: deformed blocks, coloured by displacement, and the cracks."""
from __future__ import annotations

import numpy as np

from .detection import world_vertices

__all__ = ["plot_model"]


def plot_model(model, ax=None, displacement_scale=1.0, cracks=True):
    """Draw the active blocks (displacements magnified by ``displacement_scale``) and the crack
    log (tension red, shear blue) on ``ax``; returns the axes."""
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
    if cracks:
        log = model.crack_log()
        for mode, colour, label in ((1, "red", "tension"), (2, "blue", "shear")):
            k = log["mode"] == mode
            if k.any():
                ax.plot(log["x"][k], log["y"][k], ".", ms=3, color=colour, label=label)
        if len(log["mode"]):
            ax.legend(loc="upper right")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    return ax
