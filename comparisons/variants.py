"""A case's variants: named settings ("quick", "full") or a settings mapping of the same keys.

``run(variant)`` of a case takes either; a test runs a shrunk case by passing its own settings
instead of patching the module's table.
"""
from __future__ import annotations

import copy

__all__ = ["pick_variant", "STAGED_OPTIONAL"]

# the settings the staged field cases took after their custom variants were written: Model
# options over the scene's (``solver``), early settling of every solve and level (``settle``,
# ``comparisons.staged.stage_run``) and how they are judged (``judge``, ``SolveSettings``)
STAGED_OPTIONAL = {"solver": {}, "settle": False, "judge": "response"}


def pick_variant(case: str, variants: dict, variant, optional=None) -> tuple:
    """(name, settings) of ``variant``: a key of ``variants``, or a mapping with exactly the
    keys every named variant has (its name is then "custom"), except that the keys of
    ``optional`` may be left out and then take its values (settings added after custom
    variants were written, e.g. ``{"solver": {}}``). ValueError names the problem."""
    if isinstance(variant, str):
        if variant not in variants:
            raise ValueError(f"{case}: variant must be one of {sorted(variants)} or a settings "
                             f"mapping, got {variant!r}")
        return variant, _checked(case, dict(variants[variant]))
    if not isinstance(variant, dict):
        raise ValueError(f"{case}: variant must be a name or a settings mapping, got "
                         f"{type(variant).__name__}")
    optional = copy.deepcopy(dict(optional or {}))   # the caller's defaults stay unchanged
    keys = set(next(iter(variants.values())))
    missing = keys - set(variant) - set(optional)
    unknown = set(variant) - keys
    if missing or unknown:
        raise ValueError(f"{case}: custom variant has unknown settings {sorted(unknown)} and "
                         f"lacks {sorted(missing)}")
    return "custom", _checked(case, {**optional, **variant})


def _checked(case: str, settings: dict) -> dict:
    """``settings``, its ``solver`` (if any) checked against the Model options a scene takes
    (``dem_core.workflow.scene.SOLVER_KEYS``, each value of its option's kind), its
    ``settle`` (if any) a bool, its ``edge_elements`` (if any) a bool or None and its
    ``judge`` (if any) one of ``SolveSettings``'s judges: a bad one is named before any run
    starts."""
    from dem_core.geometry.regions import check_fields, check_keys
    from dem_core.settings import JUDGES, SolverOptions
    from dem_core.workflow.scene import SOLVER_KEYS
    solver = settings.get("solver", {})
    if not isinstance(solver, dict):
        raise ValueError(f"{case}: solver must be a mapping of Model options, got {solver!r}")
    # an unknown option with a "did you mean"; a value of the wrong kind ("edge_elements": 1)
    check_keys(solver, SOLVER_KEYS, f"{case}: solver")
    check_fields(solver, SolverOptions, f"{case}: solver", partial=True)
    if not isinstance(settings.get("settle", False), bool):
        raise ValueError(f"{case}: settle must be true or false, got {settings['settle']!r}")
    edges = settings.get("edge_elements")
    if edges is not None and not isinstance(edges, bool):
        raise ValueError(f"{case}: edge_elements must be true, false or null, got "
                         f"{settings['edge_elements']!r}")
    if settings.get("judge", "budget") not in JUDGES:
        raise ValueError(f"{case}: judge must be one of {JUDGES}, got {settings['judge']!r}")
    return settings
