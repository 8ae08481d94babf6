"""Matplotlib pictures of a ContinuumModel: yield indicators and displacement."""
import numpy as np

__all__ = ["plot_yield", "plot_displacement"]


def plot_yield(model, ax=None, ever=True):
    """Cells coloured by yield mode: grey elastic, blue shear, red tension, purple both.

    Parameters
    ----------
    model : ContinuumModel
    ax : matplotlib Axes, optional
    ever : bool
        Yield at any time of the loading history (True) or at the last converged state.
    """
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap
    if ax is None:
        _, ax = plt.subplots()
    xy, tri = model.triangles()
    ind = model.yield_indicator(ever=ever)
    code = (ind["shear"] > 0).astype(int) + 2 * (ind["tension"] > 0).astype(int)
    cmap = ListedColormap(["0.85", "tab:blue", "tab:red", "tab:purple"])
    ax.tripcolor(xy[:, 0], xy[:, 1], tri, facecolors=code.astype(float), cmap=cmap,
                 vmin=-0.5, vmax=3.5, edgecolors="none")
    ax.set_aspect("equal")
    ax.set_title("yield: grey elastic, blue shear, red tension, purple both")
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
