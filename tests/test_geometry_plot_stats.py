"""The picture draws what the block system holds; statistics agree with direct counts."""
import numpy as np
import pytest

from dem_core.geometry import (GeometrySpec, JointSet, Voronoi, block_statistics,
                               build_block_system, plot_block_system, rectangle)


@pytest.fixture(scope="module")
def bs():
    return build_block_system(GeometrySpec([rectangle("rock", 0, 0, 1, 0.5)],
                                           joint_sets=[JointSet("j", 70, 0.2, dip_direction="left")],
                                           voronoi={"rock": Voronoi(0.05, seed=1)}))


def test_plot_draws_blocks_flaws_and_bold_joints(bs):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection, PolyCollection

    ax = plot_block_system(bs)
    polys = [c for c in ax.collections if isinstance(c, PolyCollection) and not isinstance(c, LineCollection)]
    lines = [c for c in ax.collections if isinstance(c, LineCollection)]
    assert len(polys[0].get_paths()) == bs.n_blocks
    n_joint = int(np.sum(bs.edge_material == bs.material_names.index("joint:j")))
    widths = [c.get_linewidths()[0] for c in lines]
    bold = lines[int(np.argmax(widths))]
    assert len(bold.get_segments()) == n_joint > 0
    assert sum(len(c.get_segments()) for c in lines) == bs.n_edges + len(bs.meta["free_edges"]["p0"])
    plt.close(ax.figure)


def test_statistics_match_direct_counts(bs):
    st = block_statistics(bs)
    assert st["blocks"] == bs.n_blocks and st["shared_edges"] == bs.n_edges
    assert st["total_area"] == pytest.approx(0.5, rel=1e-12)
    assert st["min_area"] == bs.area.min()
    assert sum(st["edges_per_material"].values()) == bs.n_edges
    assert 1.0 <= st["mean_aspect_ratio"] < st["max_aspect_ratio"] < 10
    assert st["realized_persistence"]["j"] == pytest.approx(1.0, rel=1e-9)


def test_aspect_ratio_of_a_rectangle_block():
    bs = build_block_system(GeometrySpec([rectangle("r", 0, 0, 2, 0.5)]))
    # second moments of a 2 x 0.5 rectangle: ratio of principal moments = (2 / 0.5)^2
    assert block_statistics(bs)["max_aspect_ratio"] == pytest.approx(4.0, rel=1e-12)
