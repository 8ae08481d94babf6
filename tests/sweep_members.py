"""Tiny sweep members for tests/test_sweep_mpi.py (importable by MPI worker processes): how far
a block slides down a 30 degree plane in 1,500 steps, for a given friction angle."""
import math


def slide(friction: float) -> float:
    from dem_core.materials import Material
    from dem_core.model import Model
    from dem_core.simple_blocks import from_polygons

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


if __name__ == "__main__":             # run under mpirun by the test: prints the sweep as JSON
    import json

    from comparisons.sweep import launched_under_mpi, run_sweep

    out = run_sweep(slide, [10.0, 20.0, 25.0, 35.0])
    print(json.dumps({"mpi": launched_under_mpi(), "results": out}))
