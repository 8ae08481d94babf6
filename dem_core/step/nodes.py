"""Moving the nodes of the support elements, and local damping: the leapfrog update of the
cable and liner nodes (``advance_support``, called by ``integration.advance_nodes`` right after
the blocks move, with the blocks' dt, damping and kick), their kinetic energy and the
kinetic-damping stop (``support_kinetic_energy``, ``stop_support``, ``step.relaxation``), and
``damped``, shared by the blocks (``integration.advance``), the support nodes and the deformable
blocks' gridpoints.

The support bundles (``components.Cables``, ``components.Liners``) are read by their fields
only; this module imports no component.

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

__all__ = ["damped", "move_nodes", "advance_support", "support_kinetic_energy", "stop_support"]


@njit(cache=True, inline="always")
def damped(f, v, alpha):
    """Local non-viscous damping: f - alpha |f| sign(v) (Cundall's; alpha in [0, 1))."""
    if alpha > 0.0 and v != 0.0:
        return f - alpha * abs(f) * (1.0 if v > 0.0 else -1.0)
    return f


@njit(cache=True)
def move_nodes(pos, vel, force, inv_mass, dt, kick, alpha):
    """v += damped(f) / m kick; x += v dt for every node and component of ``pos`` (n, k)
    (``kick`` s: dt, or dt / 2 on the first step after a kinetic-damping stop)."""
    for i in range(pos.shape[0]):
        for d in range(pos.shape[1]):
            vel[i, d] += damped(force[i, d], vel[i, d], alpha) * inv_mass[i] * kick
            pos[i, d] += vel[i, d] * dt


@njit(cache=True)
def advance_support(cables, liners, dt, kick, alpha):
    """The cable nodes' and the liner nodes' leapfrog step from the forces their kernels left
    in ``node_force`` (``add_cables``, ``add_liners``): translation, and a liner node's
    rotation, theta += omega dt with omega += damped(M) / I kick. Empty bundles: nothing."""
    move_nodes(cables.node_pos, cables.node_vel, cables.node_force, cables.node_inv_mass, dt,
               kick, alpha)
    move_nodes(liners.node_pos, liners.node_vel, liners.node_force, liners.node_inv_mass, dt,
               kick, alpha)
    for i in range(liners.node_pos.shape[0]):
        liners.node_omega[i] += damped(liners.node_force[i, 2], liners.node_omega[i], alpha) * \
            liners.node_inv_inertia[i] * kick
        liners.node_theta[i] += liners.node_omega[i] * dt


@njit(cache=True)
def support_kinetic_energy(cables, liners):
    """J/m: 1/2 sum v^2 / inv_mass (+ omega^2 / inv_inertia for a liner node) over the support
    nodes, inertial masses (as ``relaxation.free_kinetic_energy``): their share of the
    kinetic-damping peak test."""
    ke = 0.0
    for i in range(cables.node_pos.shape[0]):
        if cables.node_inv_mass[i] > 0.0:
            v = cables.node_vel[i]
            ke += (v[0] * v[0] + v[1] * v[1]) / cables.node_inv_mass[i]
    for i in range(liners.node_pos.shape[0]):
        if liners.node_inv_mass[i] > 0.0:
            v = liners.node_vel[i]
            ke += (v[0] * v[0] + v[1] * v[1]) / liners.node_inv_mass[i]
        if liners.node_inv_inertia[i] > 0.0:
            ke += liners.node_omega[i] * liners.node_omega[i] / liners.node_inv_inertia[i]
    return 0.5 * ke


@njit(cache=True)
def stop_support(cables, liners):
    """Zero every support node's velocity (a kinetic-damping stop)."""
    cables.node_vel[:] = 0.0
    liners.node_vel[:] = 0.0
    liners.node_omega[:] = 0.0
