"""Moving the nodes of the support elements: local damping and the leapfrog update, shared by
the blocks (``step.advance``) and the cable and liner nodes (``components/cables.py``,
``components/liner.py``).

Local damping (``damped``) is the non-viscous damping of the distinct element method: each
force component is reduced by a fixed fraction alpha of its magnitude, against the direction
of the node's velocity in that component, so the damping force does work only while a node
moves and vanishes at equilibrium without slowing a steady motion the way a viscous dashpot
would. Sources: P. A. Cundall (1987), "Distinct element models of rock and soil structure",
in E. T. Brown (ed.), Analytical and Computational Methods in Engineering Rock Mechanics,
Allen & Unwin, ch. 4; Itasca, UDEC user's manual, theory and background ("Mechanical
damping", local damping), where alpha = 0.8 is the default.
"""
from __future__ import annotations

from numba import njit

__all__ = ["damped", "move_nodes"]


@njit(cache=True, inline="always")
def damped(f, v, alpha):
    """Local non-viscous damping: f - alpha |f| sign(v) (Cundall's; alpha in [0, 1))."""
    if alpha > 0.0 and v != 0.0:
        return f - alpha * abs(f) * (1.0 if v > 0.0 else -1.0)
    return f


@njit(cache=True)
def move_nodes(pos, vel, force, inv_mass, dt, alpha):
    """v += damped(f) / m dt; x += v dt for every node and component of ``pos`` (n, k)."""
    for i in range(pos.shape[0]):
        for d in range(pos.shape[1]):
            vel[i, d] += damped(force[i, d], vel[i, d], alpha) * inv_mass[i] * dt
            pos[i, d] += vel[i, d] * dt
