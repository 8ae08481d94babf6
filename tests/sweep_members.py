"""Tiny sweep members for tests/test_sweep_mpi.py (importable by MPI worker processes): how far
a block slides down a 30 degree plane in 1,500 steps, for a given friction angle."""
import math


def slide(friction: float) -> float:
    from dem_core.contact.materials import Material
    from dem_core.model import Model
    from dem_core.geometry.simple_blocks import from_polygons

    bs = from_polygons([[(0, 0), (20, 0), (20, 1), (0, 1)], [(2, 1), (3, 1), (3, 1.5), (2, 1.5)]],
                       edge_material="joint:base", groups={"base": [0], "block": [1]})
    m = Model(bs, {"joint:*": Material(kn=1e9, ks=1e9, friction=friction)}, density=2000)
    m.fix("base")
    th = math.radians(30.0)
    m.set_gravity(1.0, direction=(math.sin(th), -math.cos(th)))
    m.cycle(1500)
    return float(m.displacement()[1, 0])


def member_pid(_member) -> int:
    """The process a member ran in (tests/test_sweep_workers.py)."""
    import os

    return os.getpid()


def member_threads(_member) -> dict:
    """The BLAS/OpenMP threads the process a member runs in may start: each loaded library's
    limit (threadpoolctl) and ``OMP_NUM_THREADS`` (tests/test_sweep_workers.py)."""
    import os

    from threadpoolctl import threadpool_info

    return {"pools": [lib["num_threads"] for lib in threadpool_info()],
            "omp_num_threads": os.environ.get("OMP_NUM_THREADS")}


if __name__ == "__main__":             # run under mpirun by the test: prints the sweep as JSON
    import json

    from comparisons.sweep import launched_under_mpi, run_sweep

    out = run_sweep(slide, [10.0, 20.0, 25.0, 35.0])
    print(json.dumps({"mpi": launched_under_mpi(), "results": out}))
