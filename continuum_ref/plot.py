"""Matplotlib pictures of a ContinuumModel: yield indicators and displacement."""
import numpy as np

__all__ = ["plot_yield", "plot_displacement"]


def plot_yield(model, ax=None, ever=True):
    """Cells coloured by yield mode: grey elastic, blue shear, red tension, purple both, with a
    legend giving each mode's share of the cells. When no cell has yielded the title and a
    note in the picture say so (an all-grey slope is then the answer, not a missing plot).

    Parameters
    ----------
    model : ContinuumModel
    ax : matplotlib Axes, optional
    ever : bool
        Yield at any time of the loading history (True) or at the last converged state.
    """
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch
    if ax is None:
        _, ax = plt.subplots()
    xy, tri = model.triangles()
    ind = model.yield_indicator(ever=ever)
    code = (ind["shear"] > 0).astype(int) + 2 * (ind["tension"] > 0).astype(int)
    colours = ["0.85", "tab:blue", "tab:red", "tab:purple"]
    ax.tripcolor(xy[:, 0], xy[:, 1], tri, facecolors=code.astype(float),
                 cmap=ListedColormap(colours), vmin=-0.5, vmax=3.5, edgecolors="none")
    ax.set_aspect("equal")
    when = "at any time of the loading" if ever else "at the last converged state"
    share = np.bincount(code, minlength=4) / max(code.size, 1)
    names = ["elastic", "shear", "tension", "shear and tension"]
    ax.legend(handles=[Patch(color=c, label=f"{n} ({100 * f:.1f} % of cells)")
                       for c, n, f in zip(colours, names, share) if f > 0 or n == "elastic"],
              fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    if share[0] == 1.0:
        ax.set_title(f"yield: no cell has yielded {when} (elastic everywhere)")
        ax.text(0.5, 0.55, "no cell has yielded:\nthe whole mesh is elastic",
                transform=ax.transAxes, ha="center", va="center", fontsize=11,
                bbox=dict(facecolor="white", alpha=0.8, edgecolor="0.5"))
    else:
        ax.set_title(f"yield {when}: grey elastic, blue shear, red tension, purple both")
    return ax


def plot_displacement(model, ax=None, scale=None):
    """Magnitude of displacement (m) at the mesh vertices on the (optionally scaled) shape."""
    import matplotlib.pyplot as plt
    if ax is None:
        _, ax = plt.subplots()
    xy, tri = model.triangles()
    u = model.displacement_at(xy)
    mag = np.linalg.norm(u, axis=1)
    s = 0.0 if scale is None else scale
    art = ax.tripcolor(xy[:, 0] + s * u[:, 0], xy[:, 1] + s * u[:, 1], tri, mag, shading="gouraud")
    plt.colorbar(art, ax=ax, label="|u| (m)")
    ax.set_aspect("equal")
    return ax
