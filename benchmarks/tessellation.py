"""Benchmark: Voronoi block generation time and peak memory.

Tessellates a 1 m x 0.5 m rectangle at the target edge length that gives about ``--blocks``
blocks, with ``--iterations`` Lloyd relaxation steps, and prints one JSON line:
blocks, target_blocks, edge_length, iterations, seconds (wall, build only), peak_mb (peak
resident set size of the process), mean_edge_length_ratio, machine.

    python benchmarks/tessellation.py --blocks 100000
"""
import argparse
import json
import os
import platform
import resource
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from dem_core.geometry import GeometrySpec, Voronoi, build_block_system, rectangle  # noqa: E402
from dem_core.geometry.stats import all_edge_lengths  # noqa: E402
from dem_core.geometry.tessellate import CELL_AREA  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=100000)
    ap.add_argument("--iterations", type=int, default=20)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args(argv)
    width, height = 1.0, 0.5
    edge = float(np.sqrt(width * height / (CELL_AREA * a.blocks)))
    spec = GeometrySpec([rectangle("rock", 0.0, 0.0, width, height)],
                        voronoi={"rock": Voronoi(edge, relax_iterations=a.iterations, seed=a.seed)})
    t0 = time.perf_counter()
    bs = build_block_system(spec)
    seconds = time.perf_counter() - t0
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # Linux: kB
    print(json.dumps({
        "benchmark": "tessellation", "blocks": bs.n_blocks, "target_blocks": a.blocks,
        "edge_length": edge, "iterations": a.iterations, "seconds": round(seconds, 3),
        "peak_mb": round(peak_mb, 1),
        "mean_edge_length_ratio": round(float(all_edge_lengths(bs).mean() / edge), 4),
        "area_rel_error": float(abs(bs.area.sum() - width * height) / (width * height)),
        "machine": {"node": platform.node(), "cpus": os.cpu_count(),
                    "python": platform.python_version()},
    }))


if __name__ == "__main__":
    main()
