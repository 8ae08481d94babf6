"""Command line: ``python -m comparisons list | run CASE [--quick|--full] [--set KEY=VALUE ...]
[--out DIR] [--resume] [--restart] [--vtk] | run-scene FILE [--set KEY=VALUE ...] [--out DIR]
[--resume] [--restart] [--vtk] [--check] [--strict] [--method dem|continuum|both] | demo``.

``run-scene FILE --method continuum`` runs the scene's stages in the continuum (its
"continuum" section: mesh size and each region's material), ``--method both`` in both methods
with one report giving each method's column and run time (``comparisons.scene_continuum.
run_continuum``); the default ``dem`` is the DEM alone.

``run-scene FILE --check`` checks the scene and builds its model (blocks and contacts, no
step), draws it to ``OUT/<scene name>/check.png`` and prints one line (blocks, contacts, the
stages); nothing is computed and nothing an earlier run kept is touched
(``comparisons.run_scene.check_scene``). A run-scene run ends with one line per stage giving its
verdict with its number (``comparisons.run_scene.verdict_lines``).

``--set`` changes one setting of the chosen variant (a key of the case's ``VARIANTS``; VALUE
is JSON, else a string), e.g. ``run adhikary --full --set 'solver={"edge_elements": true}'``
or ``run lajtai --set zone_size=0.0035``; the run is then the "custom" variant. For
``run-scene``, ``--set`` changes a top-level key of the scene file (``solver`` is laid over the
file's; ``comparisons.run_scene.apply_settings``).

``--resume`` loads what an earlier run of the same case and settings (or the same scene and
``--set``) kept in its folder's ``members/``; a kept result or checkpoint of another case
setting or scene is refused (``comparisons.store.check_kept``). ``--restart``, like a run
without ``--resume``, deletes the kept results and starts over.

Bad input (an unknown case, a scene file that does not load, an --out that cannot be written,
a kept result to resume from that belongs to another scene or settings or does not read) ends
in one line on stderr and exit status 2, before any compute. An unusual value of a scene
(``dem_core.workflow.plausibility``) is one warning line on stderr; ``--strict`` makes it bad
input."""
from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from contextlib import ExitStack, contextmanager
from pathlib import Path

from comparisons import registry, store
from comparisons.progress import Progress
from comparisons.results import write_results

PROG = "python -m comparisons"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog=PROG, description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("list", help="list the cases")
    run = sub.add_parser("run", help="run one case")
    run.add_argument("case")
    variant = run.add_mutually_exclusive_group()
    variant.add_argument("--quick", dest="variant", action="store_const", const="quick")
    variant.add_argument("--full", dest="variant", action="store_const", const="full")
    run.add_argument("--out", default="results", help="results root (default: results/)")
    run.add_argument("--seed", type=int, default=1)
    run.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                     help="change a setting of the variant (VALUE as JSON); repeatable")
    run.add_argument("--quiet", action="store_true")
    run.add_argument("--resume", action="store_true",
                     help="load the sweep members an earlier, interrupted run of this case "
                          "kept in OUT/CASE/members/ instead of running them again")
    run.add_argument("--restart", action="store_true", help=RESTART_HELP)
    run.add_argument("--vtk", action="store_true",
                     help="write each DEM model's final state for ParaView to OUT/CASE/vtk/")
    scene = sub.add_parser("run-scene", help="run a scene file (DEM): its stages, a summary, "
                                             "the stage table and a picture of the blocks")
    scene.add_argument("file", help="a scene file (JSON, docs/scenes.md)")
    scene.add_argument("--out", default="results",
                       help="results root (default: results/); writes OUT/<scene name>/")
    scene.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                       help="change a top-level key of the scene (VALUE as JSON; solver is laid "
                            "over the file's, e.g. 'solver={\"damping\": 0.5}'); repeatable")
    scene.add_argument("--resume", action="store_true",
                       help="go on after the stages an earlier, interrupted run of this scene "
                            "kept in OUT/<scene name>/members/")
    scene.add_argument("--restart", action="store_true", help=RESTART_HELP)
    scene.add_argument("--vtk", action="store_true",
                       help="write the final state for ParaView to OUT/<scene name>/")
    scene.add_argument("--check", action="store_true",
                       help="check the scene and draw the model as built to OUT/<scene name>/"
                            "check.png (blocks, joints, boundaries, points, water table); "
                            "no step is run")
    scene.add_argument("--strict", action="store_true",
                       help="refuse the scene for an unusual value (a reservoir, a density, "
                            "friction or cohesion that looks like a unit slip) instead of "
                            "warning")
    scene.add_argument("--method", choices=("dem", "continuum", "both"), default="dem",
                       help="dem (default), continuum (the scene's \"continuum\" section: "
                            "mesh size and region materials) or both, in one report")
    scene.add_argument("--quiet", action="store_true")
    demo = sub.add_parser("demo", help="the README's main job: the quick showcase case")
    demo.add_argument("--out", default="results")
    args = parser.parse_args(argv)

    if args.command == "list":
        for name in sorted(registry.CASES):
            module = registry.case_module(name)
            print(f"{name:12s} {module.DESCRIPTION}")
        return 0
    if args.command == "run-scene":
        if args.check:
            return check_scene_file(args.file, Path(args.out), settings=args.set,
                                    strict=args.strict)
        return run_scene_file(args.file, Path(args.out), args.vtk, args.quiet,
                              settings=args.set, resume=args.resume, restart=args.restart,
                              strict=args.strict, method=args.method)
    if args.command == "demo":
        return run_case(registry.DEMO_CASE, "quick", Path(args.out), seed=1, quiet=False)
    return run_case(args.case, args.variant or "quick", Path(args.out), args.seed, args.quiet,
                    resume=args.resume, vtk=args.vtk, settings=args.set,
                    restart=args.restart)


RESTART_HELP = ("delete the results an earlier run kept (e.g. of a changed scene or other "
                "settings, which --resume refuses) and start over")


def fail(message: str) -> int:
    """Bad input: one line on stderr, exit status 2 (argparse's)."""
    print(f"{PROG}: error: {message}", file=sys.stderr)
    return 2


def run_case(name: str, variant: str, out: Path, seed: int, quiet: bool, resume: bool = False,
             vtk: bool = False, settings=(), restart: bool = False) -> int:
    """Run case ``name`` and write its results to ``out/name``; its sweep members are kept in
    ``out/name/members`` (``resume``: load the kept ones; ``restart``: delete them first),
    VTK files go to ``out/name/vtk`` (``vtk``; ``comparisons.store``). ``settings``:
    "KEY=VALUE" changes of the variant (``custom_variant``). An unknown case, setting, an
    unwritable ``out`` or, resuming, a kept result of other settings (``case_source``) is
    refused before any compute (``fail``); a setting the case itself refuses (a ValueError
    from its run: its variant's and members' checks come before its sweep) is one line and
    status 2 too."""
    with ExitStack() as stack:
        try:
            module = registry.case_module(name)
            store.check_folder(Path(out) / name)
            chosen = custom_variant(module, variant, settings) if settings else variant
            stack.enter_context(store.case_output(
                Path(out) / name, resume=resume, vtk=vtk, restart=restart,
                source=case_source(module, name, variant, chosen, seed)))
        except ValueError as e:
            return fail(str(e))
        progress = Progress(name, quiet=quiet)
        t0 = time.perf_counter()
        try:
            result = module.run(variant=chosen, seed=seed, progress=progress)
        except store.StaleResult as e:
            return fail(str(e))
        except ValueError as e:                 # a setting the case refuses
            return fail(str(e) if str(e).startswith(name) else f"{name}: {e}")
    folder = write_results(result, out)
    print(f"{name} ({variant}) finished in {time.perf_counter() - t0:.1f} s")
    for metric, e in result.errors.items():
        if e.get("ours") is not None:
            rel = "" if e.get("rel_error") is None else f" ({100 * e['rel_error']:.1f} %)"
            print(f"  {metric}: ours {e['ours']:.4g}, reference {e['reference']}{rel}")
    print(f"results written to {folder.resolve()}/ (report: {(folder / 'report.md').resolve()})")
    return 0


def case_source(module, name: str, variant: str, chosen, seed: int) -> str:
    """What a case run comes from (``store.source_hash``): the case, the variant's settings
    (after ``--set``) and the seed."""
    settings = chosen if isinstance(chosen, dict) else getattr(module, "VARIANTS", {}).get(
        variant, variant)
    return store.source_hash({"case": name, "settings": settings, "seed": seed})


def custom_variant(module, variant: str, settings) -> dict:
    """The settings of ``module.VARIANTS[variant]`` with each "KEY=VALUE" of ``settings``
    applied (VALUE parsed as JSON, else taken as a string). ValueError names an item that is
    not KEY=VALUE or a KEY the variant does not have."""

    out = dict(module.VARIANTS[variant])
    for item in settings:
        key, sep, text = item.partition("=")
        if not sep or not key:
            raise ValueError(f"--set takes KEY=VALUE, got {item!r}")
        if key not in out:
            raise ValueError(f"--set {key}: not a setting of {module.__name__.split('.')[-1]}"
                             f" (settings: {', '.join(sorted(out))})")
        try:
            value = json.loads(text)
        except json.JSONDecodeError:
            value = text
        base = out[key]
        numbers = (int, float)
        if base is not None and not isinstance(value, type(base)) and not (
                isinstance(base, numbers) and isinstance(value, numbers)
                and not isinstance(value, bool)):
            raise ValueError(f"--set {key}: expected a {type(base).__name__} like {base!r}, "
                             f"got {value!r}")
        out[key] = value
    return out


@contextmanager
def scene_warnings(strict: bool = False):
    """Print each ``ScenePlausibilityWarning`` raised inside as one line on stderr, or, with
    ``strict``, refuse the scene with them (ValueError); other warnings pass on."""
    from dem_core.workflow.plausibility import ScenePlausibilityWarning

    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always", ScenePlausibilityWarning)
        yield
    lines = []
    for w in seen:
        if issubclass(w.category, ScenePlausibilityWarning):
            lines.append(str(w.message))
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    if strict and lines:
        raise ValueError("; ".join(lines) + " (refused by --strict)")
    for line in lines:
        print(f"{PROG}: warning: {line}", file=sys.stderr)


def run_scene_file(path, out: Path, vtk: bool = False, quiet: bool = False, settings=(),
                   resume: bool = False, restart: bool = False, strict: bool = False,
                   method: str = "dem") -> int:
    """``run-scene``: run a scene file's stages on the DEM model (with the ``--set`` items
    ``settings``) and write its results to ``out/<scene name>`` (``comparisons.run_scene``);
    ``resume``: go on after the stages an earlier run kept; ``restart``: delete them first;
    ``strict``: an unusual value (``scene_warnings``) refuses the scene. A file that does not
    load as a scene, an unwritable ``out``, resuming, kept stages of another scene or
    settings, or a model or stage list the checks before the first step refuse
    (``build_checked``: too large for the machine, a stage the model cannot take) are refused
    before any compute; a stage that raises ends with
    status 1 after the outputs of the stages before it are written. ``method``: "dem",
    "continuum" (the scene's "continuum" section, ``comparisons.scene_continuum.run_continuum``; no
    DEM model is built) or "both" (one report with both columns); a scene without a
    "continuum" section, or with a stage the continuum cannot run, is refused before any
    compute."""
    from comparisons.run_scene import (build_checked, load_stages, prepare,
                                       run_prepared, scene_source)
    from comparisons.scene_continuum import check_continuum

    with ExitStack() as stack:
        try:
            with scene_warnings(strict):
                scene, folder = prepare(path, out, settings)
            if method != "dem":
                check_continuum(scene)
        except ValueError as e:
            return fail(str(e))
        if method == "continuum":
            return _continuum_only(scene, folder, path, quiet)
        try:
            keep = stack.enter_context(store.case_output(
                folder, resume=resume, restart=restart, source=scene_source(scene, settings)))
            kept = load_stages(keep) if keep.resume else None
        except ValueError as e:
            return fail(str(e))
        try:
            with scene_warnings(strict):
                kept = build_checked(scene, kept)
        except ValueError as e:
            return fail(f"scene file {str(path)!r}: {e}")
        progress = Progress(scene.name, quiet=quiet)
        t0 = time.perf_counter()
        records, error = run_prepared(scene, folder, path, vtk=vtk, progress=progress,
                                      kept=kept)
    from comparisons.run_scene import verdict_lines

    fe_error = None
    if method == "both":
        dem_time = json.loads((folder / "summary.json").read_text())["runtime_s"]
        fe_records, fe_error = _continuum_column(scene, folder, path, progress,
                                                 dem=(records, dem_time))
    n = len(records)
    print(f"{Path(path).name}: {n} stage{'s' if n != 1 else ''} run, "
          f"{time.perf_counter() - t0:.1f} s with the outputs")
    print(f"results written to {folder.resolve()}/ (report: {(folder / 'report.md').resolve()})")
    print("Verdicts:")
    for line in verdict_lines(records, error, scene.stages):
        print(f"  {line}")
    if method == "both":
        _print_continuum(fe_records, fe_error)
    if error is not None:
        print(f"{PROG}: stage {len(records)} stopped the run: {type(error).__name__}: {error}",
              file=sys.stderr)
        return 1
    return 1 if fe_error is not None else 0


def _continuum_column(scene, folder, path, progress, dem=None):
    from comparisons.scene_continuum import run_continuum

    return run_continuum(scene, folder, path, progress=progress, dem=dem)


def _print_continuum(records, error) -> None:
    from comparisons.scene_continuum import continuum_line

    print("Continuum:")
    for r in records:
        print(f"  {continuum_line(r)}")
    if error is not None:
        print(f"{PROG}: the continuum run stopped: {type(error).__name__}: {error}",
              file=sys.stderr)


def _continuum_only(scene, folder, path, quiet) -> int:
    """``run-scene --method continuum``: the scene's stages in the continuum alone."""
    progress = Progress(scene.name, quiet=quiet)
    t0 = time.perf_counter()
    records, error = _continuum_column(scene, folder, path, progress)
    print(f"{Path(path).name}: {len(records)} continuum stage{'s' if len(records) != 1 else ''}"
          f" run, {time.perf_counter() - t0:.1f} s with the outputs")
    print(f"results written to {folder.resolve()}/ (report: {(folder / 'report.md').resolve()})")
    _print_continuum(records, error)
    return 1 if error is not None else 0


def check_scene_file(path, out: Path, settings=(), strict: bool = False) -> int:
    """``run-scene FILE --check``: check the scene, build its model (no step), draw it to
    ``out/<scene name>/check.png`` and print one line: the blocks, contacts and stages
    (``comparisons.run_scene.check_scene``). A scene that does not load or whose stages or
    monitoring points do not fit its model is refused (``fail``, status 2)."""
    from comparisons.run_scene import check_scene

    try:
        with scene_warnings(strict):
            _, line = check_scene(path, out, settings)
    except ValueError as e:
        return fail(str(e))
    print(line)
    return 0
