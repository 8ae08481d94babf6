"""The list of cases: name -> module. A case module defines

- ``DESCRIPTION`` (one line),
- ``run(variant: str, seed: int, progress: Progress) -> CaseResult``.

Modules are imported only when listed or run, so a case that needs DOLFINx does not make the
others depend on it.
"""
from __future__ import annotations

import importlib

CASES = {
    "lajtai": "comparisons.lajtai",
    "adhikary": "comparisons.adhikary",
    "longtan": "comparisons.longtan",
    "highwood": "comparisons.highwood",
    "lornex": "comparisons.lornex",
    "underdip": "comparisons.underdip",
    "coal_buckling": "comparisons.coal_buckling",
    "checkerboard": "comparisons.checkerboard",
    "common_toppling": "comparisons.common_toppling",
}

DEMO_CASE = "adhikary"


def case_module(name: str):
    """Import and return the module of case ``name`` (ValueError naming the known cases)."""
    if name not in CASES:
        known = ", ".join(sorted(CASES)) or "(none)"
        raise ValueError(f"unknown case {name!r}; known cases: {known}")
    return importlib.import_module(CASES[name])
