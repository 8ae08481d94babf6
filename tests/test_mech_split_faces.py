"""A side split into collinear pieces (where neighbours' corners meet it) is one face to touch.

Blocks at a region boundary (a Voronoi zone against a big joint block, a bed line) have sides
split at every corner of the cells along them. A vertex that presses into such a side ties
with every piece (same normal, same distance); the search must give it the piece it projects
onto. (Before: it took whichever piece came first by round-off, and when that piece lay
farther along the side than the search margin the vertex got no contact at all; in the
Longtan slope a vertex went 6.7 mm deep into a joint block that way and the model blew up.)
"""
import pytest

from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.geometry.simple_blocks import from_polygons

H = 1e-5                  # the block's bottom is pressed this far into the base's top, m


def block_on_split_top(x0):
    """Base [0, 2] x [0, 1] with its top split at x = 0.6 and 1.4 (fixed), and a 0.3 x 0.2
    block from x0, pressed H into it (no shared edge: the contacts come from the search)."""
    base = [(0, 0), (2, 0), (2, 1), (1.4, 1), (0.6, 1), (0, 1)]
    block = [(x0, 1 - H), (x0 + 0.3, 1 - H), (x0 + 0.3, 1.2 - H), (x0, 1.2 - H)]
    bs = from_polygons([base, block], groups={"base": [0], "block": [1]})
    m = Model(bs, {"flaw:*": Material(kn=1e9, ks=1e9, friction=30.0)}, density=2000,
              damping=0.0, new_contact_material="flaw:rock", search_margin=1e-3)
    m.fix("base")
    m.search()
    return m


@pytest.mark.parametrize("x0", [0.1, 0.25, 0.7, 1.0, 1.5, 1.65])
def test_both_bottom_corners_touch_the_split_top_wherever_they_are(x0):
    m = block_on_split_top(x0)
    c = m.contacts
    corners = {int(c.vertex_a[k]) for k in range(c.n) if c.block_a[k] == 1}
    assert len(corners) == 2 and c.n == 2            # one contact per bottom corner
    for k in range(c.n):
        assert c.normal_b[k, 1] == pytest.approx(-1.0, abs=1e-9)  # into the base: its top
    # each contact's point lies on the piece under its corner
    off = m.props.vertex_offsets
    for k in range(c.n):
        x = m.state.pos[1, 0] + m.props.local_vertices[c.vertex_a[k], 0]
        e = c.edge_b[k] - off[0]
        x_start, x_end = [(2.0, 1.4), (1.4, 0.6), (0.6, 0.0)][e - 2]
        assert x_end <= x <= x_start


def test_a_block_resting_across_the_split_top_carries_its_weight():
    """Under gravity the two contacts carry the weight: no corner sinks through the top."""
    m = block_on_split_top(0.45)                      # corners over two different pieces
    m.set_gravity(1.0)
    m.set_options(damping=0.8)
    m.cycle(4000)
    overlap = H - (m.state.pos[1, 1] - m.state.pos0[1, 1])
    weight = 2000 * 0.3 * 0.2 * 9.81                  # N per m out of plane
    # an elastic overlap of the order weight / (kn x width) (3.9 um), not a fall
    assert 0.0 < overlap < 3 * weight / (1e9 * 0.3)
    assert abs(m.state.vel[1, 1]) < 1e-4
