"""Command line: ``python -m comparisons list | run CASE [--quick|--full] [--out DIR] [--resume]
[--vtk] | demo``."""
from __future__ import annotations

import argparse
import time
from pathlib import Path

from comparisons import registry, store
from comparisons.progress import Progress
from comparisons.results import write_results


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m comparisons", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("list", help="list the cases")
    run = sub.add_parser("run", help="run one case")
    run.add_argument("case")
    variant = run.add_mutually_exclusive_group()
    variant.add_argument("--quick", dest="variant", action="store_const", const="quick")
    variant.add_argument("--full", dest="variant", action="store_const", const="full")
    run.add_argument("--out", default="results", help="results root (default: results/)")
    run.add_argument("--seed", type=int, default=1)
    run.add_argument("--quiet", action="store_true")
    run.add_argument("--resume", action="store_true",
                     help="load the sweep members an earlier, interrupted run of this case "
                          "kept in OUT/CASE/members/ instead of running them again")
    run.add_argument("--vtk", action="store_true",
                     help="write each DEM model's final state for ParaView to OUT/CASE/vtk/")
    demo = sub.add_parser("demo", help="the README's main job: the quick showcase case")
    demo.add_argument("--out", default="results")
    args = parser.parse_args(argv)

    if args.command == "list":
        for name in sorted(registry.CASES):
            module = registry.case_module(name)
            print(f"{name:12s} {module.DESCRIPTION}")
        return 0
    if args.command == "demo":
        return run_case(registry.DEMO_CASE, "quick", Path(args.out), seed=1, quiet=False)
    return run_case(args.case, args.variant or "quick", Path(args.out), args.seed, args.quiet,
                    resume=args.resume, vtk=args.vtk)


def run_case(name: str, variant: str, out: Path, seed: int, quiet: bool, resume: bool = False,
             vtk: bool = False) -> int:
    """Run case ``name`` and write its results to ``out/name``; its sweep members are kept in
    ``out/name/members`` (``resume``: load the kept ones), VTK files go to ``out/name/vtk``
    (``vtk``; ``comparisons.store``)."""
    module = registry.case_module(name)
    progress = Progress(name, quiet=quiet)
    t0 = time.perf_counter()
    with store.case_output(Path(out) / name, resume=resume, vtk=vtk):
        result = module.run(variant=variant, seed=seed, progress=progress)
    folder = write_results(result, out)
    print(f"{name} ({variant}) finished in {time.perf_counter() - t0:.1f} s")
    for metric, e in result.errors.items():
        if e.get("ours") is not None:
            rel = "" if e.get("rel_error") is None else f" ({100 * e['rel_error']:.1f} %)"
            print(f"  {metric}: ours {e['ours']:.4g}, reference {e['reference']}{rel}")
    print(f"results written to {folder.resolve()}/ (report: {(folder / 'report.md').resolve()})")
    return 0
