"""The serial contact kernel compiled by numba's plain and parallel pipelines (issue 29 item 5).

    .venv/bin/python benchmarks/trials/numba_pipelines.py [--blocks 10000] [--calls 200]

The contact loop (``dem_core.contact.forces.chunk_forces``, the serial kernel when called with
``j = -1``) is compiled with ``parallel=True`` (and no ``prange``)
because the same source through numba's plain pipeline runs many times slower
(docs/performance.md). This benchmark recompiles the kernel's Python source both ways
(``njit`` and ``njit(parallel=True)``, no cache) and a third way: the plain pipeline with one
pass added after its rewrites, ``Simplify``, which runs on the typed IR what numba's parfor
pass runs before it looks for loops (``numba.core.ir_utils.simplify``: copy propagation, dead
code removal, CFG simplification). It calls each on the same arrays of a bonded
Voronoi specimen at rest under gravity (``throughput.specimen``; the law is elastic there, no
bond breaks, so repeated calls do the same work), takes the best of five batches, and counts
in each version's LLVM IR the calls to numba's reference-count runtime (``NRT_incref``,
``NRT_decref``) and all calls. One JSON line to stdout and results/benchmarks/numba_pipelines.json
(the committed record: benchmarks/results/numba_pipelines.json).
"""
from __future__ import annotations

import argparse
import json
import platform
import sys
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
BENCHMARKS = HERE.parent                  # a trial uses the benchmarks' modules (trials/README.md)
sys.path.insert(0, str(BENCHMARKS))
sys.path.insert(0, str(BENCHMARKS.parent))

import outdir  # noqa: E402


def simplify_pipeline():
    """A numba compiler class: the plain nopython pipeline plus ``ir_utils.simplify`` after
    its rewrites (module docstring)."""
    from numba.core import ir_utils
    from numba.core.compiler import CompilerBase, DefaultPassBuilder
    from numba.core.compiler_machinery import FunctionPass, register_pass
    from numba.core.typed_passes import NopythonRewrites

    @register_pass(mutates_CFG=True, analysis_only=False)
    class Simplify(FunctionPass):
        _name = "simplify_as_parfors_do"

        def __init__(self):
            FunctionPass.__init__(self)

        def run_pass(self, state):
            ir_utils.simplify(state.func_ir, state.typemap, state.calltypes, state.metadata)
            return True

    class PlainWithSimplify(CompilerBase):
        def define_pipelines(self):
            pm = DefaultPassBuilder.define_nopython_pipeline(self.state)
            pm.add_pass_after(Simplify, NopythonRewrites)
            pm.finalize()
            return [pm]

    return PlainWithSimplify


def best_ns_per_contact(fn, args, n_contacts, calls):
    """Best of five batches of ``calls // 5`` calls, ns per contact."""
    fn(*args)                                   # compile
    batch, best = max(1, calls // 5), float("inf")
    for _ in range(5):
        t0 = time.perf_counter()
        for _ in range(batch):
            fn(*args)
        best = min(best, (time.perf_counter() - t0) / batch)
    return 1e9 * best / n_contacts


def ir_counts(fn) -> dict:
    ir = next(iter(fn.inspect_llvm().values()))
    return {"NRT_incref": ir.count("@NRT_incref("), "NRT_decref": ir.count("@NRT_decref("),
            "calls": ir.count(" call "), "ir_lines": ir.count("\n")}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=10_000)
    ap.add_argument("--calls", type=int, default=200)
    a = ap.parse_args()
    from numba import njit

    import throughput
    from dem_core.contact import forces
    from dem_core.contact.materials import Material
    from dem_core.model import Model
    from dem_core.step.state import no_parallel

    flaw = Material(kn=40e9, ks=20e9, tensile_strength=1.1e6, cohesion=1.2e6, friction=37)
    m = Model(throughput.specimen(a.blocks), {"flaw:*": flaw, "boundary:*": flaw},
              density=1700, history_every=10**9)
    m.fix("base")
    m.set_gravity(50.0)
    m.cycle(20)
    # the serial kernel: chunk_forces with j = -1 and the empty Parallel bundle
    args = (m.contacts, m.table.strength_array(), m.state, m.corners, m.zone_state,
            no_parallel(), False, -1, m.cracks, m.time)
    source = forces.chunk_forces.py_func
    out = {"benchmark": "numba_pipelines", "machine": f"{platform.node()} {platform.machine()} {platform.platform()}",
           "blocks": m.n_blocks, "contacts": int(m.contacts.n)}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")          # "parallel=True but nothing to parallelise"
        for name, fn in (("plain", njit(source)), ("parallel", njit(parallel=True)(source)),
                         ("plain_with_simplify", njit(pipeline_class=simplify_pipeline())(source))):
            t0 = time.perf_counter()
            fn(*args)
            out[name] = {"compile_and_first_call_s": round(time.perf_counter() - t0, 2)}
            out[name]["ns_per_contact"] = round(best_ns_per_contact(fn, args, m.contacts.n,
                                                                    a.calls), 2)
            out[name].update(ir_counts(fn))
    out["plain_over_parallel"] = round(out["plain"]["ns_per_contact"]
                                       / out["parallel"]["ns_per_contact"], 2)
    out["plain_with_simplify_over_parallel"] = round(
        out["plain_with_simplify"]["ns_per_contact"] / out["parallel"]["ns_per_contact"], 2)
    line = json.dumps(out)
    print(line)
    (outdir.results_dir() / "numba_pipelines.json").write_text(line + "\n")


if __name__ == "__main__":
    main()
