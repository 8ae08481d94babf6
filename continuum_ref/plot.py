"""Matplotlib pictures of a ContinuumModel: yield indicators, displacement, stress, and the
state at a stage's end (``stage_figure``: excavated cells left out)."""
import numpy as np

__all__ = ["plot_yield", "plot_displacement", "plot_shear_stress", "stage_figure",
           "live_cells"]


def live_cells(model):
    """(ncells,) bool: the cells still there (not excavated; every cell for a model that
    cannot excavate)."""
    n = len(model.triangles()[1])
    gone = model.excavated() if hasattr(model, "excavated") else np.zeros(n, bool)
    return ~np.asarray(gone, bool)


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
    live = live_cells(model)
    ind = model.yield_indicator(ever=ever)
    code = ((ind["shear"] > 0).astype(int) + 2 * (ind["tension"] > 0).astype(int))[live]
    tri = tri[live]
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


def plot_displacement(model, ax=None, scale=None, unit="m"):
    """Magnitude of displacement at the mesh vertices (in ``unit``, "m" or "mm") on the shape
    moved by ``scale`` times the displacement (None: not moved); excavated cells left out."""
    import matplotlib.pyplot as plt
    if ax is None:
        _, ax = plt.subplots()
    xy, tri = model.triangles()
    tri = tri[live_cells(model)]
    u = model.displacement_at(xy)
    mag = np.linalg.norm(u, axis=1) * (1e3 if unit == "mm" else 1.0)
    s = 0.0 if scale is None else scale
    art = ax.tripcolor(xy[:, 0] + s * u[:, 0], xy[:, 1] + s * u[:, 1], tri, mag, shading="gouraud")
    plt.colorbar(art, ax=ax, label=f"|u| ({unit})")
    ax.set_aspect("equal")
    return ax


def plot_shear_stress(model, ax=None):
    """The largest in-plane shear stress tau_max = sqrt(((sxx - syy) / 2)^2 + sxy^2) of each
    cell (MPa; effective stress where a pore pressure is set), excavated cells left out."""
    import matplotlib.pyplot as plt
    if ax is None:
        _, ax = plt.subplots()
    xy, tri = model.triangles()
    live = live_cells(model)
    s = model.stress()
    tau = np.hypot(0.5 * (s[:, 0] - s[:, 1]), s[:, 3]) / 1e6
    art = ax.tripcolor(xy[:, 0], xy[:, 1], tri[live], facecolors=tau[live], cmap="viridis",
                       edgecolors="none")
    plt.colorbar(art, ax=ax, label="tau_max (MPa)")
    ax.set_aspect("equal")
    return ax


def _magnification(model, live):
    """A factor that makes the largest displacement of the live cells' nodes about 5 % of the
    model's size (1 when that is already visible, or nothing moved)."""
    xy, tri = model.triangles()
    nodes = np.unique(tri[live])
    u = np.abs(model.displacement_at(xy[nodes])).max() if nodes.size else 0.0
    size = float(np.ptp(xy[:, 0]) + np.ptp(xy[:, 1])) / 2
    if u <= 0.0 or u >= 0.05 * size:
        return 1.0
    k = 0.05 * size / u
    return float(10 ** np.floor(np.log10(k)))


def stage_figure(model, heading, water=None):
    """The state of ``model`` at a stage's end, excavated cells left out: displacement (mm)
    on the shape moved by the magnification in its title, the points yielding at that state
    (``plot_yield``, ``ever=False``), and tau_max (MPa). ``heading``: what the state is (the stage, its
    verdict), the figure's title. ``water``: the water table's points [(x, y), ...] in m,
    drawn as a blue line on each panel, or None."""
    import matplotlib.pyplot as plt

    live = live_cells(model)
    k = _magnification(model, live)
    fig, axes = plt.subplots(3, 1, figsize=(8.5, 11), constrained_layout=True)
    plot_displacement(model, axes[0], scale=k, unit="mm")
    axes[0].set_title(f"displacement (mm), shape moved x {k:g}", fontsize=9)
    plot_yield(model, axes[1], ever=False)       # yielding now: where the mechanism is
    axes[1].title.set_fontsize(9)
    plot_shear_stress(model, axes[2])
    axes[2].set_title("largest shear stress tau_max (MPa, effective)", fontsize=9)
    for ax in axes:
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        if water is not None:
            xw, yw = np.asarray(water, float).T
            # cyan over black: seen on the yield panel's blue shear cells and the colour maps
            ax.plot(xw, yw, color="k", lw=2.6, zorder=5)
            ax.plot(xw, yw, color="cyan", lw=1.4, ls="--", zorder=6)
            ax.annotate("water table", (xw[0], yw[0]), xytext=(3, 4), zorder=6,
                        textcoords="offset points", fontsize=7,
                        bbox=dict(facecolor="white", alpha=0.7, edgecolor="none", pad=1))
    gone = int(np.sum(~live))
    fig.suptitle(heading + (f"\n{gone} excavated cells not drawn" if gone else ""),
                 fontsize=10)
    return fig
