"""Stage lists a scene often starts with, built from its materials.

``strong_then_real``: the thesis's initialisation of a jointed slope under gravity and in-situ
stress (the intact rock made strong while the stresses settle, then given back its real
strength, so the model starts in equilibrium and uncracked by the initialisation).
"""
from __future__ import annotations

from .stages import ChangeMaterial, Gravity, Solve


def strong_then_real(materials: dict, names, factor=1e3, g_level=1.0, ratio=1e-5,
                     max_steps=200_000) -> list:
    """The thesis's initialisation as stages: the ``names`` materials made ``factor`` times
    stronger (T and c), gravity at ``g_level`` solved to ``ratio``, then the real strengths
    given back (a strength change moves no stress, so the model starts in equilibrium with its
    real strengths and no failure the initialisation caused)."""
    if not factor >= 1:
        raise ValueError(f"strong_then_real: factor {factor!r} must be >= 1")
    strong, real = [], []
    for n in names:
        if n not in materials:
            raise ValueError(f"strong_then_real: no material {n!r}; materials are "
                             f"{sorted(materials)}")
        m = materials[n]
        strong.append(ChangeMaterial(n, {"tensile_strength": m.tensile_strength * factor,
                                         "cohesion": m.cohesion * factor}))
        real.append(ChangeMaterial(n, {"tensile_strength": m.tensile_strength,
                                       "cohesion": m.cohesion}))
    return strong + [Gravity(g_level), Solve(ratio=ratio, max_steps=max_steps)] + real
