"""One bonded edge in pure bending: the two contacts of a shared edge act as one linear
interface element (``forces.edge_correction``), so the edge turns with the elastic rotational
stiffness kn L^3 / 12 and breaks at the elastic moment T L^2 / 6."""
import numpy as np
import pytest

from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.geometry.simple_blocks import from_polygons

KN, T, L = 1e10, 1e6, 0.5           # Pa/m, Pa, m (edge length)


def pair(threads=1):
    """A fixed block and a free one sharing a vertical edge of length L, no gravity."""
    left = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, L], [0.0, L]])
    right = left + [1.0, 0.0]
    bs = from_polygons([left, right], groups={"fixed": [0], "free": [1]})
    m = Model(bs, {"*": Material(kn=KN, ks=KN, tensile_strength=T, cohesion=10 * T,
                                 friction=40.0)}, density=2500.0, threads=threads,
              edge_elements=True)
    m.fix("fixed")
    return m


def test_a_bonded_edge_turns_with_the_elastic_rotational_stiffness():
    m = pair()
    moment = 0.5 * T * L ** 2 / 6
    m.apply_load("free", moment=moment)
    assert m.solve(ratio=1e-9, max_steps=100_000).verdict == "equilibrium"
    theta = m.state.theta[1]
    assert theta == pytest.approx(moment / (KN * L ** 3 / 12), rel=1e-3)
    # each end carries the peak of the linear stress, +-6 M / L^2 (compression +)
    assert sorted(m.contacts.live("sn")) == pytest.approx([-6 * moment / L ** 2,
                                                            6 * moment / L ** 2], rel=1e-3)


@pytest.mark.parametrize("factor, breaks", [(0.98, False), (1.02, True)])
def test_a_bonded_edge_breaks_at_the_elastic_moment(factor, breaks):
    m = pair()
    m.apply_load("free", moment=factor * T * L ** 2 / 6)
    m.solve(ratio=1e-9, max_steps=100_000, failure_displacement=0.01)
    assert (m.crack_counts()["tension"] > 0) == breaks


def test_the_threaded_kernel_gives_the_same_bits_with_edge_elements(monkeypatch):
    monkeypatch.setattr("dem_core.step.threads.parallel.MIN_CONTACTS", 0)     # a small model, threaded
    monkeypatch.setattr("dem_core.step.threads.region.MIN_CONTACTS", 0)
    a, b = pair(1), pair(2)
    for m in (a, b):
        m.apply_load("free", fx=1e3, moment=0.3 * T * L ** 2 / 6)
        m.cycle(2000)
    assert np.array_equal(a.state.pos, b.state.pos)
    assert np.array_equal(a.state.theta, b.state.theta)
