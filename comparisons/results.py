"""What a case run produces, and writing it to ``results/<case>/``.

``summary.json`` holds ``case``, ``variant``, ``seed``, ``methods`` (one object per method run,
each with its metrics and ``runtime_s``), ``reference`` (thesis and experimental values),
``errors`` (each compared metric against its reference), ``notes`` (assumptions),
``versions`` and ``results_hash`` (``case_hash``: two runs with the same hash gave the same
numbers, bit for bit). Curves go to CSV, figures to PNG, and ``report.md`` puts the figures and
a table of ours against the references side by side.
"""
from __future__ import annotations

import json
import math
import platform
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from dem_core.output.fingerprint import is_wall_clock, results_hash


@dataclass
class Curve:
    """A table of numbers written as CSV: ``columns`` names, ``rows`` (n, len(columns))."""

    columns: list
    rows: np.ndarray


@dataclass
class CaseResult:
    case: str
    variant: str
    seed: int
    methods: dict = field(default_factory=dict)
    reference: dict = field(default_factory=dict)
    errors: dict = field(default_factory=dict)
    curves: dict = field(default_factory=dict)
    figures: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)

    def add_error(self, name: str, ours: float, reference, method: str = "dem") -> dict:
        """Record ``ours`` against ``reference`` (a number or a [low, high] range).

        For a range the error is the distance to the nearest end (0 inside the range); the
        relative error divides by the reference value (the range's mid-point).
        """
        entry = metric_error(ours, reference)
        entry["method"] = method
        self.errors[name] = entry
        return entry


def metric_error(ours: float, reference) -> dict:
    """Absolute and relative error of ``ours`` against a value or a [low, high] range."""
    if ours is None or (isinstance(ours, float) and not math.isfinite(ours)):
        return {"ours": None, "reference": reference, "abs_error": None, "rel_error": None}
    if isinstance(reference, (list, tuple)):
        low, high = float(reference[0]), float(reference[1])
        mid = 0.5 * (low + high)
        err = 0.0 if low <= ours <= high else min(abs(ours - low), abs(ours - high))
    else:
        mid = float(reference)
        err = abs(ours - mid)
    rel = err / abs(mid) if mid != 0 else None
    return {"ours": float(ours), "reference": reference, "abs_error": float(err),
            "rel_error": None if rel is None else float(rel)}


def software_versions() -> dict:
    """Versions of the stack (DOLFINx/gmsh only if importable)."""
    import numba
    import scipy

    from comparisons.sweep import usable_cores

    versions = {"python": platform.python_version(), "numpy": np.__version__,
                "numba": numba.__version__, "scipy": scipy.__version__,
                "machine": f"{platform.machine()} {platform.system()} ({usable_cores()} cores)"}
    for name in ("dolfinx", "gmsh", "shapely"):
        try:
            module = __import__(name)
            versions[name] = getattr(module, "__version__", "?")
        except ImportError:
            pass
    return versions


def _jsonable(value):
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, (np.floating, float)):
        v = float(value)
        return v if math.isfinite(v) else None
    if isinstance(value, (np.integer,)):
        return int(value)
    return value


def write_results(result: CaseResult, out_root: Path) -> Path:
    """Write the case's summary, CSVs, figures and report; return the case folder."""
    out = Path(out_root) / result.case
    out.mkdir(parents=True, exist_ok=True)
    summary = {
        "case": result.case, "variant": result.variant, "seed": result.seed,
        "methods": result.methods, "reference": result.reference, "errors": result.errors,
        "notes": result.notes, "versions": software_versions(),
        "written": time.strftime("%Y-%m-%d %H:%M:%S"), "results_hash": case_hash(result),
    }
    (out / "summary.json").write_text(json.dumps(_jsonable(summary), indent=2))
    for name, curve in result.curves.items():
        rows = np.asarray(curve.rows, dtype=float).reshape(-1, len(curve.columns))
        np.savetxt(out / f"{name}.csv", rows, delimiter=",", header=",".join(curve.columns),
                   comments="", fmt="%.8g")
    for name, fig in result.figures.items():
        fig.savefig(out / f"{name}.png", dpi=110, bbox_inches="tight")
        _release(fig)
    (out / "report.md").write_text(render_report(result, summary["versions"],
                                                 summary["results_hash"]))
    return out


def case_hash(result: CaseResult) -> str:
    """``dem_core.output.fingerprint.results_hash`` of the case's numbers as computed, before
    anything is rounded for the files: case, variant, seed, ``methods``, ``errors`` and every
    curve (columns and rows), without wall-clock times (``runtime_s``, a curve's run-time
    columns: ``fingerprint.is_wall_clock``). Not recomputable from the files (the CSVs keep 8
    digits); compare two reports' hashes instead (docs/output.md, "Same input, same bits")."""
    curves = {}
    for name, curve in result.curves.items():
        rows = np.asarray(curve.rows, dtype=float).reshape(-1, len(curve.columns))
        keep = [i for i, c in enumerate(curve.columns) if not is_wall_clock(c)]
        curves[name] = {"columns": [curve.columns[i] for i in keep], "rows": rows[:, keep]}
    return results_hash({"case": result.case, "variant": result.variant, "seed": result.seed,
                         "methods": result.methods, "errors": result.errors,
                         "curves": curves})


def _release(fig) -> None:
    """Let pyplot forget a written figure (it stays usable: a Figure can be saved again after
    ``plt.close``), so a session that runs many cases does not keep every figure open."""
    import matplotlib.pyplot as plt

    plt.close(fig)


def render_report(result: CaseResult, versions: dict, digest: str | None = None) -> str:
    """The report's Markdown; ``digest``: the results hash (``case_hash``), on its own line
    under the title."""
    lines = [f"# {result.case} ({result.variant} variant, seed {result.seed})", ""]
    if digest is not None:
        lines += [f"Results hash: `{digest}` (the same hash: the same numbers, bit for bit; "
                  f"docs/output.md)", ""]
    lines += ["## Ours against the references", "",
              "| metric | method | ours | reference | abs. error | rel. error |",
              "|---|---|---|---|---|---|"]
    for name, e in result.errors.items():
        rel = "-" if e.get("rel_error") is None else f"{100 * e['rel_error']:.1f} %"
        ours = "-" if e.get("ours") is None else f"{e['ours']:.4g}"
        abs_err = "-" if e.get("abs_error") is None else f"{e['abs_error']:.3g}"
        lines.append(f"| {name} | {e.get('method', '')} | {ours} | {e['reference']} | "
                     f"{abs_err} | {rel} |")
    lines += ["", "## Run time", "", "| method | run time (s) |", "|---|---|"]
    for method, metrics in result.methods.items():
        lines.append(f"| {method} | {metrics.get('runtime_s', float('nan')):.1f} |")
    if result.figures:
        lines += ["", "## Figures", ""]
        lines += [f"![{name}]({name}.png)" for name in result.figures]
    if result.curves:
        lines += ["", "## Data", ""]
        lines += [f"- `{name}.csv`: {', '.join(c.columns)}" for name, c in result.curves.items()]
    if result.notes:
        lines += ["", "## Assumptions and notes", ""] + [f"- {n}" for n in result.notes]
    lines += ["", "## Software", ""] + [f"- {k}: {v}" for k, v in versions.items()]
    return "\n".join(lines) + "\n"
