"""The tree's architecture as tests: no import cycle among the project's modules (tests,
benchmarks and examples included), dem_core's layers import only downwards, every subpackage
states what it holds, and the glossary of docs/architecture.md names what the code uses."""
from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("dem_core", "continuum_ref", "comparisons")
SCRIPT_FOLDERS = ("tests", "benchmarks", "examples")


def module_files() -> dict:
    """{dotted module name: path}: the packages' modules, and the script folders' files under
    their folder's name (``tests.test_scene``), as sys.path inserts make them importable."""
    out = {}
    for pkg in PACKAGES:
        for p in (ROOT / pkg).rglob("*.py"):
            parts = list(p.relative_to(ROOT).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            out[".".join(parts)] = p
    for folder in SCRIPT_FOLDERS:
        for p in (ROOT / folder).glob("*.py"):
            out[f"{folder}.{p.stem}"] = p
    return out


def imports_of(name: str, path: Path, known: dict) -> set:
    """The project modules ``name`` imports, anywhere in its file (function-level imports
    too: a cycle through a deferred import is still a cycle of the design)."""
    tree = ast.parse(path.read_text())
    is_pkg = path.name == "__init__.py"
    package = name if is_pkg else name.rpartition(".")[0]
    folder = name.partition(".")[0] if name.partition(".")[0] in SCRIPT_FOLDERS else None
    found = set()

    def add(mod):
        if mod in known and mod != name:
            found.add(mod)
        elif folder and f"{folder}.{mod}" in known:
            found.add(f"{folder}.{mod}")
        else:                               # a script importing a sibling folder's file
            for other in SCRIPT_FOLDERS:
                if f"{other}.{mod}" in known and "." not in mod:
                    found.add(f"{other}.{mod}")
                    break

    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                add(a.name)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[:len(base) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            for a in node.names:
                if f"{mod}.{a.name}" in known:
                    add(f"{mod}.{a.name}")
                else:
                    add(mod)
    return found


def cycles(graph: dict) -> list:
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def import_graph() -> dict:
    known = module_files()
    return {name: imports_of(name, path, known) for name, path in known.items()}


def test_no_import_cycle():
    found = cycles(import_graph())
    assert not found, f"import cycles: {found}"


def test_a_cycle_is_found():
    """The cycle finder itself finds a cycle (so the test above can fail)."""
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_benchmarks_do_not_import_tests():
    graph = import_graph()
    bad = sorted((m, t) for m, deps in graph.items() if m.startswith("benchmarks.")
                 for t in deps if t.startswith("tests."))
    assert not bad, bad


# What each layer of dem_core may import (docs/architecture.md; each subpackage's docstring)
MAY_NOT_IMPORT = {
    "dem_core.geometry": ("dem_core.contact", "dem_core.step", "dem_core.components",
                          "dem_core.deformable", "dem_core.workflow", "dem_core.output",
                          "dem_core.model"),
    "dem_core.contact": ("dem_core.workflow", "dem_core.output", "dem_core.model"),
    "dem_core.step": ("dem_core.workflow", "dem_core.output", "dem_core.model"),
    "dem_core.components": ("dem_core.workflow", "dem_core.model"),
    "dem_core.deformable": ("dem_core.workflow", "dem_core.output", "dem_core.model"),
    "dem_core.output": ("dem_core.workflow", "dem_core.model"),
}


def test_layers_import_downwards():
    graph = import_graph()
    bad = []
    for mod, deps in graph.items():
        for layer, banned in MAY_NOT_IMPORT.items():
            if mod == layer or mod.startswith(layer + "."):
                bad += [(mod, d) for d in deps if d.startswith(banned)]
    assert not bad, bad
    assert not any(d.startswith(("continuum_ref", "comparisons"))
                   for m, deps in graph.items() if m.startswith("dem_core") for d in deps)


def test_every_subpackage_states_what_it_holds_and_may_import():
    for init in (ROOT / "dem_core").rglob("__init__.py"):
        doc = ast.get_docstring(ast.parse(init.read_text())) or ""
        if init.parent.name in ("geometry",):
            assert doc, init
            continue
        if init.parent == ROOT / "dem_core":
            assert "public API" in doc, init
            continue
        assert "Holds" in doc or "holds" in doc, init
        assert "import" in doc, init


def test_old_module_paths_import_the_new_modules_with_a_warning():
    """One release of grace: ``dem_core.law`` is ``dem_core.contact.law``, with a warning that
    names the new path; every moved name resolves (dem_core._moved.MOVED)."""
    import importlib
    import subprocess
    import sys

    from dem_core._moved import MOVED

    code = ("import warnings, importlib\n"
            "warnings.simplefilter('error')\n"
            "import dem_core.law\n")
    run = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True)
    assert run.returncode != 0 and "dem_core.law moved to dem_core.contact.law" in run.stderr
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        for old, new in MOVED.items():
            assert importlib.import_module(old) is importlib.import_module(new), old
        from dem_core.step import run_steps
        from dem_core.step.run import run_steps as new_run_steps
    assert run_steps is new_run_steps


def test_the_public_api():
    import dem_core
    from dem_core.contact.materials import Material
    from dem_core.model import Model
    from dem_core.workflow.scene import Scene, build_model
    from dem_core.workflow.stages import run_stages
    assert (dem_core.Scene, dem_core.build_model, dem_core.run_stages, dem_core.Model,
            dem_core.Material) == (Scene, build_model, run_stages, Model, Material)
    assert set(dem_core.__all__) >= {"Scene", "build_model", "run_stages", "Model", "Material"}
