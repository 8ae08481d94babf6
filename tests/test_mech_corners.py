"""Corners: a vertex at another block's corner touches the face it rests on, not the end face.

Two blocks meet corner on corner where a joint reaches a free end (the ends of the direct-shear
specimen): the lower block's corner sits a little inside the upper block, closer to the upper
block's free end face (2 um) than to its joint face (10 um, the joint's compression). A contact
with the end face would be a spring across the joint, growing with the slip; the support rule
(``detection._supports``) gives the vertex the joint face, the one its block's edge lies along.
"""
import math

import pytest

from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.geometry.simple_blocks import from_polygons

G = 9.81
EPS, H = 2e-6, 1e-5          # the corner's distance inside the end face and the joint face, m


def corner_on_corner(friction, divide=False):
    """Base [0, 2] x [0, 1] (fixed) and a 1 x 0.5 block whose left end is EPS left of the base's
    corner, pressed H into the base's top (no shared edge: all contacts come from the search);
    ``divide``: the interfaces divided at each search (``divide_interfaces``)."""
    bs = from_polygons([[(0, 0), (2, 0), (2, 1), (0, 1)],
                        [(-EPS, 1 - H), (1 - EPS, 1 - H), (1 - EPS, 1.5 - H), (-EPS, 1.5 - H)]],
                       groups={"base": [0], "block": [1]})
    # a search margin of 1 mm: the faces' distances (2 and 10 um) differ by more than the
    # search's tie tolerance (1e-3 margin)
    m = Model(bs, {"flaw:*": Material(kn=1e9, ks=1e9, friction=friction)}, density=2000,
              damping=0.0, new_contact_material="flaw:rock", search_margin=1e-3,
              divide_interfaces=divide)
    m.fix("base")
    m.search()
    return m


def test_corner_inside_the_end_face_touches_the_joint_face():
    m = corner_on_corner(20.0)
    c = m.contacts
    base_corner = 3                                   # vertex (0, 1) of the base
    mine = [k for k in range(c.n) if c.vertex_a[k] == base_corner]
    assert len(mine) == 1
    k = mine[0]
    # the block's bottom face: the normal from the base into the block is +y, not +x
    assert c.normal_b[k, 1] == pytest.approx(1.0, abs=1e-9)


def slid(m):
    return m.state.pos0[1, 0] - m.state.pos[1, 0]


def cycle_until_slid(m, distance):
    while slid(m) < distance:
        m.cycle(20)
    return m.time, m.state.vel[1, 0]


@pytest.mark.parametrize("divide", [False, True])
@pytest.mark.parametrize("theta, friction", [(30.0, 20.0)])
def test_block_slides_off_a_corner_on_corner_start_with_coulomb_acceleration(theta, friction,
                                                                             divide):
    """Sliding left moves the base's corner along the block's joint face: no lock, the
    acceleration is g (sin theta - cos theta tan phi) as on a plane, with the contact lengths
    as made and with the interfaces divided. Measured between 0.03 and 0.35 m of slide (it
    tips off the base's corner after 0.5 m), not over a count of steps: the division changes
    the contacts' lengths and with them the time step (the base corner's contact is made 1.0 m
    long on a 0.5 m overlap and divided to half of it)."""
    m = corner_on_corner(friction, divide)
    th = math.radians(theta)
    m.set_gravity(1.0, direction=(-math.sin(th), -math.cos(th)))
    t1, v1 = cycle_until_slid(m, 0.03)
    t2, v2 = cycle_until_slid(m, 0.35)
    a = -(v2 - v1) / (t2 - t1)
    expected = G * (math.sin(th) - math.cos(th) * math.tan(math.radians(friction)))
    assert a == pytest.approx(expected, rel=0.01)
    assert abs(m.state.pos[1, 1] - m.state.pos0[1, 1]) < 1e-4      # on the joint, not off it
