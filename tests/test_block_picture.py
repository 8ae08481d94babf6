"""Block pictures: the cracks are drawn as the shared edges whose bonds broke, on the
blocks that carry them, with the mode of each edge's first break; joints as thin lines; the
displacement magnification is a round number that makes the motion visible; a continuum yield
picture says so when nothing has yielded."""
import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402

from dem_core.geometry import (GeometrySpec, JointLine, Voronoi, build_block_system,  # noqa: E402
                               rectangle)
from dem_core.contact.materials import Material  # noqa: E402
from dem_core.model import Model  # noqa: E402
from dem_core.output.plot import (SHEAR, TENSION, JOINT, block_picture, draw_picture,  # noqa: E402
                           magnification, plot_model)


@pytest.fixture(scope="module")
def pulled_bar():
    """A 6 x 3 cm Voronoi bar with a strong joint along its axis, pulled apart until flaws
    break in tension."""
    spec = GeometrySpec(regions=[rectangle("rock", 0, 0, 0.06, 0.03),
                                 rectangle("left", -0.01, 0, 0, 0.03),
                                 rectangle("right", 0.06, 0, 0.07, 0.03)],
                        joints=[JointLine("axis", [(0.0, 0.015), (0.06, 0.015)],
                                          regions=["rock"])],
                        voronoi={"rock": Voronoi(edge_length=0.006, seed=1, relax_iterations=20)})
    strong = dict(kn=1e12, ks=1e12, tensile_strength=3e6, cohesion=3e6, friction=35)
    m = Model(build_block_system(spec),
              {"flaw:*": Material(kn=1e12, ks=1e12, tensile_strength=1e6, cohesion=3e6,
                                  friction=35),
               "joint:*": Material(**strong),
               "boundary:*": Material(kn=1e12, ks=1e12, breakable=False)}, density=2500)
    m.fix("left")
    m.set_velocity("right", vx=0.05, vy=0.02)
    m.cycle(300)
    assert m.cracks.count[0] > 0
    return m


def world(m, b):
    """(k, 2) present world vertices of block b."""
    p, s = m.props, m.state
    lv = p.local_vertices[p.vertex_offsets[b]:p.vertex_offsets[b + 1]]
    c, sn = np.cos(s.theta[b]), np.sin(s.theta[b])
    return s.pos[b] + lv @ np.array([[c, sn], [-sn, c]])


def test_cracks_are_the_broken_edges_on_their_blocks(pulled_bar):
    m = pulled_bar
    pic = block_picture(m, cracks=None, joints="joint:")
    bs, log = m.blocks, m.crack_log()
    kind, blk = pic["segment_kind"], pic["segment_block"]
    # every broken pair is drawn once, with the mode of its first break
    pairs = {}
    for a, b, mode in zip(log["block_a"], log["block_b"], log["mode"]):
        pairs.setdefault(frozenset((int(a), int(b))), int(mode))
    cracked = [(frozenset((int(bs.edge_block_a[e]), int(bs.edge_block_b[e]))))
               for e in range(bs.n_edges)]
    expect = sorted(mode for pair, mode in pairs.items() if pair in cracked)
    assert sorted(kind[kind != JOINT].tolist()) == expect and len(expect) > 0
    n_joint = int(np.sum([bs.material_names[k].startswith("joint:") for k in bs.edge_material]))
    assert np.count_nonzero(kind == JOINT) == n_joint > 0
    # drawn at scale 1, each segment's ends are vertices of its block as it is now
    _, ax = plt.subplots()
    draw_picture(pic, ax, 1.0)
    segs = [s for c in ax.collections if isinstance(c, LineCollection)
            for s in c.get_segments()]
    assert len(segs) == len(kind)
    order = np.argsort(kind, kind="stable")            # drawn kind by kind: joint, T, S
    for seg, b in zip(segs, blk[order]):
        gap = np.abs(world(m, b)[None, :, :] - np.asarray(seg)[:, None, :]).sum(axis=2)
        assert gap.min(axis=1).max() < 1e-12
    plt.close("all")


def test_plot_model_keeps_its_dots_and_draws_segments_when_asked(pulled_bar):
    m = pulled_bar
    ax = plot_model(m)                                   # as before: blocks and crack dots
    assert [len(c.get_paths()) for c in ax.collections] == [m.n_blocks]
    assert sum(len(line.get_xdata()) for line in ax.lines) == m.cracks.count[0]
    ax = plot_model(m, displacement_scale=10.0, crack_lines=True, joints="joint:",
                    rupture=[(0.02, 0.0), (0.02, 0.03)])
    lines = [c for c in ax.collections if isinstance(c, LineCollection)]
    polys = [c for c in ax.collections if isinstance(c, PolyCollection)
             and not isinstance(c, LineCollection)]
    assert len(polys) == 1 and [c.get_label() for c in lines][0] == "joints"
    assert len(ax.lines) == 1                            # the rupture polyline, no dots
    labels = ax.get_legend_handles_labels()[1]
    assert "rupture surface" in labels and "cracks, tension" in labels
    plt.close("all")


def test_magnification_is_round_and_shows_the_motion():
    pic = {"pos0": np.array([[0.0, 0.0], [1.0, 0.0]]), "active": np.array([1, 1]),
           "pos": np.array([[0.0, 0.0], [1.0, 0.0013]])}
    k = magnification(pic, fraction=0.05)
    assert k == 20.0                                     # 0.05 / 0.0013 = 38 -> 20
    assert k * 0.0013 <= 0.05
    pic["pos"] = np.array([[0.0, 0.0], [1.3, 0.0]])       # already large: true scale
    assert magnification(pic) == 1.0
    pic["pos"] = pic["pos0"].copy()
    assert magnification(pic) == 1.0
    assert TENSION == 1 and SHEAR == 2                   # the crack log's modes


class _Mesh:
    """What plot_yield reads of a ContinuumModel: two triangles and their yield fractions."""

    def __init__(self, shear):
        self.shear = np.asarray(shear, float)

    def triangles(self):
        return np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float), np.array([[0, 1, 2],
                                                                            [0, 2, 3]])

    def yield_indicator(self, ever=True):
        return {"shear": self.shear, "tension": np.zeros(2)}


def test_a_yield_picture_says_when_nothing_has_yielded():
    from continuum_ref.plot import plot_yield

    ax = plot_yield(_Mesh([0.0, 0.0]))
    assert "no cell has yielded" in ax.get_title()
    assert any("elastic" in t.get_text() for t in ax.texts)
    ax = plot_yield(_Mesh([0.0, 0.5]))
    assert "no cell" not in ax.get_title() and not ax.texts
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["elastic (50.0 % of cells)", "shear (50.0 % of cells)"]
    plt.close("all")
