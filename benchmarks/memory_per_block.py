"""Peak memory per DEM block and per continuum cell: the numbers the size checks estimate with
(``dem_core.geometry.budget.BYTES_PER_BLOCK``, ``continuum_ref.mesh.BYTES_PER_CELL``).

    .venv/bin/python benchmarks/memory_per_block.py [--dem 0.05 0.025] [--continuum 0.1 0.05]

Each size runs in a fresh process: after the imports and a small warm-up build (so that the
libraries' own memory is not counted), the process's peak resident memory (VmHWM, reset
through /proc/self/clear_refs) is read around the build. DEM: a 10 m x 5 m rectangle of
Voronoi blocks of the given edge lengths (m), 20 relaxation steps, and its ``Model``.
Continuum: the same rectangle meshed at the given element sizes (m), its ``ContinuumModel``
(P2) and one elastic gravity solve (the LU factorisation is the largest part). The marginal
bytes per block (cell) between the two sizes are what a larger model adds
(docs/performance.md, "Memory per block and per cell"). Writes
``results/benchmarks/memory_per_block.json``.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from outdir import results_dir  # noqa: E402

ROOT = HERE.parent


def _status(key: str) -> int:
    """A /proc/self/status field in bytes."""
    with open("/proc/self/status") as fh:
        text = fh.read()
    return int(text.split(f"{key}:")[1].split()[0]) * 1024


def _reset_peak() -> int:
    """Reset the peak (VmHWM) to now; the resident bytes now."""
    import gc
    gc.collect()
    with open("/proc/self/clear_refs", "w") as fh:
        fh.write("5")
    return _status("VmRSS")


def dem(edge: float) -> dict:
    """Peak bytes of a Voronoi build and its Model at ``edge`` (m), in this process."""
    from dem_core.contact.materials import Material
    from dem_core.geometry import GeometrySpec, Voronoi, build_block_system
    from dem_core.geometry.regions import rectangle
    from dem_core.model import Model

    def spec(w, h, e):
        return GeometrySpec([rectangle("rock", 0, 0, w, h)],
                            voronoi={"rock": Voronoi(e, relax_iterations=20)})
    Model(build_block_system(spec(1, 1, 0.3)), {"*": Material(kn=1e10, ks=1e10)}, 2500.0)
    base = _reset_peak()
    bs = build_block_system(spec(10, 5, edge))
    Model(bs, {"*": Material(kn=1e10, ks=1e10, friction=30)}, density=2500.0)
    return {"edge_length": edge, "blocks": int(bs.n_blocks), "bytes": _status("VmHWM") - base}


def continuum(h: float) -> dict:
    """Peak bytes of a mesh, its ContinuumModel and one elastic solve at size ``h`` (m)."""
    import numpy as np

    from continuum_ref.materials import Elastic
    from continuum_ref.mesh import mesh_from_geometry
    from continuum_ref.model import ContinuumModel
    from dem_core.geometry import GeometrySpec
    from dem_core.geometry.regions import rectangle

    geo = GeometrySpec([rectangle("rock", 0, 0, 10, 5)])

    def solve(size):
        md = mesh_from_geometry(geo, size)
        m = ContinuumModel(md, Elastic(1e9, 0.25), 2500.0)
        m.fix(lambda x: np.isclose(x[1], 0.0))
        m.fix(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], 10.0), components=(0,))
        assert m.solve_gravity(1.0).converged
        return md.mesh.topology.index_map(2).size_local
    solve(1.0)
    base = _reset_peak()
    cells = solve(h)
    return {"h": h, "cells": int(cells), "bytes": _status("VmHWM") - base}


def marginal(rows, count) -> float:
    """Bytes per item between the smallest and the largest of ``rows``."""
    a, b = min(rows, key=lambda r: r[count]), max(rows, key=lambda r: r[count])
    return (b["bytes"] - a["bytes"]) / (b[count] - a[count])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dem", type=float, nargs="+", default=[0.05, 0.025])
    ap.add_argument("--continuum", type=float, nargs="+", default=[0.1, 0.05])
    ap.add_argument("--one", nargs=2, help=argparse.SUPPRESS)     # kind, size: in a child
    a = ap.parse_args(argv)
    if a.one:
        print(json.dumps((dem if a.one[0] == "dem" else continuum)(float(a.one[1]))))
        return
    out = {}
    for kind, sizes, count in (("dem", a.dem, "blocks"), ("continuum", a.continuum, "cells")):
        rows = []
        for size in sizes:
            run = subprocess.run([sys.executable, __file__, "--one", kind, str(size)],
                                 capture_output=True, text=True, check=True, cwd=ROOT)
            rows.append(json.loads(run.stdout.strip().splitlines()[-1]))
            print(kind, rows[-1], flush=True)
        out[kind] = {"runs": rows, f"bytes_per_{count[:-1]}": marginal(rows, count)}
        print(f"{kind}: {out[kind][f'bytes_per_{count[:-1]}']:.0f} bytes per {count[:-1]}")
    path = results_dir() / "memory_per_block.json"
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
