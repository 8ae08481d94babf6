"""A local sweep runs at most ``comparisons.sweep.local_workers()`` members side by side: the
cores this process may use, or ``COMPARISONS_WORKERS``."""
import os

import pytest

from comparisons.sweep import local_workers, pool_threads, run_sweep, usable_cores
from sweep_members import member_pid, member_threads


def test_comparisons_workers_caps_the_pool(monkeypatch):
    monkeypatch.setenv("COMPARISONS_WORKERS", "1")
    lines = []
    assert run_sweep(member_pid, [1, 2, 3], workers=2, progress=lines.append) == [os.getpid()] * 3
    assert all(line.endswith("(serial)") for line in lines) and len(lines) == 3
    monkeypatch.setenv("COMPARISONS_WORKERS", "2")
    pids = run_sweep(member_pid, [1, 2, 3], workers=2)
    assert os.getpid() not in pids                  # in a pool's processes


def test_without_it_the_cap_is_the_cores_this_process_may_use(monkeypatch):
    monkeypatch.delenv("COMPARISONS_WORKERS", raising=False)
    assert local_workers() == usable_cores() == len(os.sched_getaffinity(0))


@pytest.mark.parametrize("bad", ["0", "-1", "two", "1.5", ""])
def test_a_bad_value_is_named(monkeypatch, bad):
    monkeypatch.setenv("COMPARISONS_WORKERS", bad)
    with pytest.raises(ValueError, match=f"COMPARISONS_WORKERS.*{bad!r}"):
        local_workers()


@pytest.mark.skipif(usable_cores() < 2, reason="a pool needs two cores")
def test_pool_processes_share_the_cores_among_their_blas_threads(monkeypatch):
    from threadpoolctl import threadpool_limits

    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("COMPARISONS_WORKERS", "2")
    cores = usable_cores()
    with threadpool_limits(limits=cores):          # this process: a thread per core
        here = member_threads(0)
        pooled = run_sweep(member_threads, [1, 2], workers=2)
    assert max(here["pools"]) == cores and here["omp_num_threads"] is None
    share = pool_threads(2)
    assert share == cores // 2
    for member in pooled:                           # each of two processes: half the cores
        assert member["pools"] and max(member["pools"]) == share
        assert member["omp_num_threads"] == str(share)
