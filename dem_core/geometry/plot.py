"""A matplotlib picture of a block system: blocks coloured by region, flaws thin, joints bold."""
from __future__ import annotations

import numpy as np


def plot_block_system(bs, ax=None, show_joints=True, region_colors=None, linewidth=0.3):
    """Draw the blocks (face colour per region), flaw edges thin, joint edges bold.

    Parameters
    ----------
    bs : BlockSystem
    ax : matplotlib Axes, optional (a new figure if None)
    region_colors : list of colours per region, optional (tab20 default)
    linewidth : float, line width of flaw/boundary edges (joints are 4x as wide)

    Returns
    -------
    ax
    """
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection, PolyCollection

    if ax is None:
        _, ax = plt.subplots(figsize=(8, 6))
    cmap = plt.get_cmap("tab20")
    colors = region_colors or [cmap(i % 20) for i in range(len(bs.region_names))]
    polys = [bs.block_vertices(b) for b in range(bs.n_blocks)]
    face = [colors[r] for r in bs.region_id]
    ax.add_collection(PolyCollection(polys, facecolors=face, edgecolors="none", alpha=0.6))
    segs = np.stack([bs.edge_p0, bs.edge_p1], axis=1)
    is_joint = np.array([n.startswith("joint:") for n in bs.material_names], bool)
    jmask = is_joint[bs.edge_material] if bs.n_edges else np.zeros(0, bool)
    ax.add_collection(LineCollection(segs[~jmask], colors="0.25", linewidths=linewidth))
    free = bs.meta.get("free_edges")
    if free is not None and len(free["p0"]):
        ax.add_collection(LineCollection(np.stack([free["p0"], free["p1"]], axis=1),
                                         colors="k", linewidths=2 * linewidth))
    if show_joints and jmask.any():
        ax.add_collection(LineCollection(segs[jmask], colors="crimson", linewidths=4 * linewidth))
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    return ax
