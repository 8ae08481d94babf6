"""The threads' many-step region (``dem_core.step.threads.region``) and its atomics: the serial numbers bit
for bit with any number of chunks and threads, one thread alone included (no thread ever waits
for a chunk nobody took), and the thresholds that pick it."""
import numba
import numpy as np
import pytest
from numba import njit, prange

from dem_core.step.threads import parallel, region
from dem_core.step.threads.atomics import compare_exchange, fetch_add, load_acquire, store_release
from dem_core.geometry import GeometrySpec, Voronoi, build_block_system, rectangle
from dem_core.contact.materials import Material
from dem_core.model import Model
from dem_core.step.run import NEED_SEARCH, UNSTABLE

TWO = pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs 2 threads")


def _specimen(threads=1, edge=0.006, width=0.1):
    bs = build_block_system(GeometrySpec(
        [rectangle("rock", 0, 0, width, 0.05), rectangle("base", 0, -0.01, width, 0)],
        voronoi={"rock": Voronoi(edge_length=edge, seed=2)}))
    flaw = Material(kn=1e10, ks=5e9, tensile_strength=2e4, cohesion=4e4, friction=35)
    model = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=2500.0, threads=threads)
    model.fix("base")
    model.set_gravity(300.0)                    # strong enough to break bonds and search
    return model


def _run_region(m, n, chunks, threads):
    """``n`` steps of ``m`` through ``region.run_steps_region`` with ``chunks`` chunks on
    ``threads`` threads, searching when it asks (as ``Model._run`` does)."""
    before = numba.get_num_threads()
    numba.set_num_threads(threads)
    try:
        done = 0
        while done < n:
            par = parallel.parallel_bundle(m.contacts, m.n_blocks, chunks, m.edge_elements)
            steps, m.time, status, _ = region.run_steps_region(
                n - done, m.time, m.integrator(), m.world(), m.parts().gravity, par)
            assert status != UNSTABLE
            m.step += steps
            done += steps
            if status == NEED_SEARCH:
                m.search()
    finally:
        numba.set_num_threads(before)


@pytest.mark.parametrize("chunks, threads", [(2, 1), (3, 2)])
def test_region_is_bit_for_bit_serial_with_any_threads(chunks, threads):
    """Two chunks on one thread (the first thread takes every chunk of every step), and three
    chunks on two threads: the serial step's numbers and crack log."""
    if threads > numba.config.NUMBA_NUM_THREADS:
        pytest.skip("needs 2 threads")
    serial, threaded = _specimen(), _specimen()
    serial.cycle(2000)
    _run_region(threaded, 2000, chunks, threads)
    assert threaded.step == 2000
    cracks = serial.crack_counts()
    assert cracks["tension"] + cracks["shear"] > 0 and serial.contacts.n == threaded.contacts.n
    assert np.array_equal(serial.state.pos, threaded.state.pos)
    assert np.array_equal(serial.state.theta, threaded.state.theta)
    assert serial.time == threaded.time
    np.testing.assert_array_equal(serial.crack_log()["x"], threaded.crack_log()["x"])


def test_the_region_is_used_from_its_own_threshold():
    """Gravity alone: threads from ``region.MIN_CONTACTS`` live contacts; with another force
    (a load) only from ``parallel.MIN_CONTACTS``."""
    m = _specimen(threads=2, edge=0.004, width=0.6)          # ~2,000 blocks
    assert region.MIN_CONTACTS <= m.contacts.n < parallel.MIN_CONTACTS
    assert m.threads_bundle(m.parts()).first.shape[0] == 3             # two chunks
    m.apply_load("rock", fx=1.0)
    assert m.threads_bundle(m.parts()).first.shape[0] == 0             # serial


@njit(parallel=True)
def _count(counter, n):
    for _t in prange(2):
        for _k in range(n):
            fetch_add(counter, 0, 1)


@njit
def _exchange(a):
    first = compare_exchange(a, 0, 0, 5)        # 0 -> 5
    second = compare_exchange(a, 0, 0, 7)       # not 0 any more: no change
    store_release(a, 1, 9)
    return first, second, a[0], load_acquire(a, 1)


@TWO
def test_atomics():
    numba.set_num_threads(2)
    counter = np.zeros(1, np.int64)
    _count(counter, 200_000)
    assert counter[0] == 400_000                # no increment lost between the threads
    assert _exchange(np.zeros(2, np.int64)) == (True, False, 5, 9)
    with pytest.raises(Exception, match="int64"):
        _exchange(np.zeros(2, np.float64))
