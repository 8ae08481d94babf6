"""The threaded contact kernel gives bit-for-bit the serial results (same sums, same order)."""
import numba
import numpy as np
import pytest

from dem_core.geometry import GeometrySpec, Voronoi, build_block_system, rectangle
from dem_core.contact.materials import Material
from dem_core.model import Model


def _run(threads, edges=False, load=False, rounding=0.0, soft=False):
    bs = build_block_system(GeometrySpec(
        [rectangle("rock", 0, 0, 0.1, 0.05), rectangle("base", 0, -0.01, 0.1, 0)],
        voronoi={"rock": Voronoi(edge_length=0.006, seed=2)}))
    # soft: softening flaws (contact.softening), 25 and 12 times their snap-back limits
    flaw = Material(kn=1e10, ks=5e9, tensile_strength=2e4, cohesion=4e4, friction=35,
                    fracture_energy_I=0.5 if soft else 0.0,
                    fracture_energy_II=2.0 if soft else 0.0)
    model = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=2500.0, threads=threads,
                  edge_elements=edges, rounding=rounding)
    model.fix("base")
    model.set_gravity(300.0)                    # strong enough to break bonds and search
    if load:                # a force besides gravity: the threaded step's two-region shape
        model.apply_load("rock", fx=50.0)
    model.cycle(3000)
    return model


# gravity alone: one parallel region per step (contacts, gravity and moves of the owned
# blocks); with a load: the contact region, the other forces, the serial integration
@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs 2 threads")
@pytest.mark.parametrize("edges, load, rounding, soft", [
    (False, False, 0.0, False), (True, False, 0.0, False), (True, True, 0.0, False),
    (False, False, 2e-4, False), (True, True, 0.0, True), (False, False, 2e-4, True)])
def test_threaded_kernel_is_bit_for_bit_serial(monkeypatch, edges, load, rounding, soft):
    monkeypatch.setattr("dem_core.step.threads.parallel.MIN_CONTACTS", 0)     # a small model, threaded
    monkeypatch.setattr("dem_core.step.threads.region.MIN_CONTACTS", 0)
    serial = _run(1, edges, load, rounding, soft)
    threaded = _run(2, edges, load, rounding, soft)
    if soft:                    # softening, not yet fully softened within these steps
        assert (serial.contacts.live("damage") > 0).sum() > 10
        for name in ("damage", "work_fracture", "work_friction"):
            assert np.array_equal(serial.contacts.live(name), threaded.contacts.live(name))
        assert np.array_equal(serial.state.work, threaded.state.work)
    else:
        assert serial.crack_counts()["tension"] + serial.crack_counts()["shear"] > 0
    assert np.array_equal(serial.state.pos, threaded.state.pos)
    assert np.array_equal(serial.state.theta, threaded.state.theta)
    np.testing.assert_array_equal(serial.crack_log()["x"], threaded.crack_log()["x"])
    assert serial.contacts.n == threaded.contacts.n


def test_thread_count_is_checked():
    with pytest.raises(ValueError, match="threads"):
        _run(0)


@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs 2 threads")
def test_threaded_integration_pass_is_bit_for_bit_serial():
    """``integration.advance_parallel`` (the two-region step, from MIN_THREADED_BLOCKS blocks
    up) moves every block as ``integration.advance`` does: five steps of random forces on a
    specimen of several chunks."""
    from dem_core.step.state import copy_bundle
    from dem_core.step.integration import advance, advance_parallel
    bs = build_block_system(GeometrySpec(
        [rectangle("rock", 0, 0, 0.3, 0.15), rectangle("base", 0, -0.01, 0.3, 0)],
        voronoi={"rock": Voronoi(edge_length=0.004, seed=2)}))      # ~1,000 blocks: 4 chunks
    flaw = Material(kn=1e10, ks=5e9, tensile_strength=2e4, cohesion=4e4, friction=35)
    model = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=2500.0)
    model.fix("base")
    numba.set_num_threads(2)
    one, two = copy_bundle(model.state), copy_bundle(model.state)
    integ = model.integrator()
    for _ in range(5):
        model.state.force[:] = np.random.default_rng(0).normal(size=model.state.force.shape)
        for s in (one, two):
            s.force[:] = model.state.force
        assert advance(one, model.props, integ, integ.dt) == \
            advance_parallel(two, model.props, integ, integ.dt)
    assert model.n_blocks > 2 * 256 and np.abs(one.omega).max() > 0
    for name in ("pos", "theta", "rot", "rot_half", "vel", "omega"):
        assert np.array_equal(getattr(one, name), getattr(two, name)), name


def test_the_threaded_step_is_one_region_only_when_gravity_is_the_only_other_force():
    """``step.only_gravity`` picks the one-region step: true with gravity alone, false as soon
    as another force component is in the scene (here an applied load)."""
    from dem_core.step.run import only_gravity
    bs = build_block_system(GeometrySpec([rectangle("rock", 0, 0, 0.02, 0.01)]))
    flaw = Material(kn=1e10, ks=5e9, tensile_strength=2e4, cohesion=4e4, friction=35)
    model = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=2500.0)
    model.set_gravity(9.81)
    assert only_gravity(model.parts(), model.zone_state)
    model.apply_load("rock", fx=1.0)
    assert not only_gravity(model.parts(), model.zone_state)


@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs 2 threads")
@pytest.mark.parametrize("load", [False, True])
def test_an_unstable_threaded_step_is_reported(monkeypatch, load):
    """A time step far above the critical one: both shapes of the threaded step stop and name
    an unstable block, as the serial step does."""
    from dem_core.model import ModelUnstable
    monkeypatch.setattr("dem_core.step.threads.parallel.MIN_CONTACTS", 0)
    monkeypatch.setattr("dem_core.step.threads.region.MIN_CONTACTS", 0)
    bs = build_block_system(GeometrySpec(
        [rectangle("rock", 0, 0, 0.1, 0.05), rectangle("base", 0, -0.01, 0.1, 0)],
        voronoi={"rock": Voronoi(edge_length=0.006, seed=2)}))
    flaw = Material(kn=1e10, ks=5e9, tensile_strength=2e4, cohesion=4e4, friction=35)
    model = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=2500.0, threads=2,
                  dt=1e-3)
    model.fix("base")
    model.set_gravity(300.0)
    if load:
        model.apply_load("rock", fx=50.0)
    with pytest.raises(ModelUnstable, match=r"block \d+.*critical step"):
        model.cycle(100)
