"""Forces across a section (dem_core.output.sections) against statics: a block resting on a
fixed base under its weight W and an applied moment M0 takes from the base the force (0, W)
and, about the middle of its base, the moment -M0 (its weight acts through that point), on
both contact models; on edge elements with the heel lifted too (e = M0 / W beyond b / 6)."""
import sys
from pathlib import Path

import numpy as np
import pytest

from dem_core.output.sections import section_force, thrust_line

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from scenes import block_on_plane  # noqa: E402  (benchmarks/scenes.py)

G, RHO, B, H = 9.81, 2000.0, 1.0, 0.5


def rested(edge_elements, eccentricity):
    m = block_on_plane(40.0, width=B, height=H, edge_elements=edge_elements)
    m.set_options(damping=0.8)
    m.set_gravity(1.0, g=G)
    weight = RHO * G * B * H
    m.apply_load("block", moment=eccentricity * weight)
    m.cycle(20_000)
    return m, weight


@pytest.mark.parametrize("edge_elements", [True, False])
@pytest.mark.parametrize("eccentricity", [0.0, B / 12, B / 4])
def test_the_base_carries_the_weight_and_the_applied_moment(edge_elements, eccentricity):
    m, weight = rested(edge_elements, eccentricity)
    block = np.zeros(m.n_blocks, bool)
    block[1] = True
    sec = section_force(m, block, ~block, (2.0 + B / 2, 1.0))
    assert sec["contacts"] >= 2
    assert sec["force"] == pytest.approx([0.0, weight], abs=1e-4 * weight)
    assert sec["moment"] == pytest.approx(-eccentricity * weight, abs=1e-4 * weight * B)
    c = m.contacts
    heel_open = bool((c.sn[:c.n] == 0.0).any())
    # the heel lifts beyond the kern of the edge's linear field (b / 6); the end springs'
    # two point forces both stay compressed up to e = b / 2
    assert heel_open == (edge_elements and eccentricity > B / 6)


def test_the_thrust_line_of_the_rested_block_is_where_the_moment_puts_it():
    """The block cut from the base at station 0 (the base's top) along +y: the thrust is its
    weight and it crosses the cut b / 4 from the middle, on the side the moment turns to
    (counter-clockwise: the reaction moves to -x)."""
    m, weight = rested(True, B / 4)
    members = np.ones(m.n_blocks, bool)
    line = thrust_line(m, members, origin=(2.0 + B, 0.5), along=(0.0, 1.0), normal=(1.0, 0.0),
                       thickness=B, stations=[0.6])
    assert line["N"][0] == pytest.approx(weight, rel=1e-4)
    assert line["e_over_t"][0] == pytest.approx(-0.25, abs=1e-4)


def test_masks_that_overlap_or_do_not_fit_are_refused():
    m, _ = rested(False, 0.0)
    both = np.ones(m.n_blocks, bool)
    with pytest.raises(ValueError, match="share blocks"):
        section_force(m, both, both, (0.0, 0.0))
    with pytest.raises(ValueError, match="masks over the model's 2 blocks"):
        section_force(m, np.ones(3, bool), np.zeros(3, bool), (0.0, 0.0))
