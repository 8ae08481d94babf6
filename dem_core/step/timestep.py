"""The time step: a function of the bundles and the options (``Model`` calls it whenever the
contacts, the support or the fixity change).

Central differences are stable for ``dt < 2 / omega_max`` (e.g. Belytschko, Liu & Moran 2000,
Nonlinear Finite Elements, ch. 6). omega_max^2 is bounded block by block (Gershgorin 1931:
every eigenvalue lies within a row's diagonal plus its off-diagonal sum, here
``run.frequency_bound``), or taken as the largest eigenvalue of the contact stiffness
(``critical_step``, ``SolverOptions.step_estimate = "eigen"``, or "auto" on rigid blocks). The step is
``dt = safety x 2 / omega_max`` unless a fixed ``dt`` is given.

Three more things set omega_max:

- a free block with no contact may meet one before the next search: it is bounded by a
  contact of its own size made of the new-contact material (the *guard*);
- cables and liners add their grout and bond springs to the blocks they hold
  (``components.support.support_stiffness``); their nodes get the inertial masses that keep
  them inside the blocks' step (``support.set_node_masses``);
- deformable blocks' gridpoints have their own bound (``deformable.component``).

With mass scaling (quasi-static runs) a block whose bound exceeds the median of the free
blocks' gets that much more inertial mass (gravity keeps the real mass), so slivers do not set
the step; a gridpoint the same, against the same target.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..components import support
from ..deformable import component as zone_kernels
from . import critical_step
from .run import frequency_bound
from .state import FIX_ROT, FIX_X, FIX_Y

__all__ = ["TimeStep", "choose_timestep"]


class TimeStep(NamedTuple):
    dt: float | None            # s; None: no contacts yet and no fixed dt
    critical_dt: float          # s: 2 / omega_max (inf when nothing can move)


def choose_timestep(world, cables, liners, options, table, previous_dt) -> TimeStep:
    """The step for ``world`` (``world.World``) with ``cables``, ``liners`` and the
    ``SolverOptions`` (its ``new_contact_material`` resolved: the guard's material in
    ``table``, the MaterialTable); sets the inertial masses of the blocks, gridpoints and
    support nodes. ``previous_dt``: kept when nothing bounds the step and no dt is fixed."""
    p = world.props
    new = options.new_contact_material
    guard_k = None
    if new is not None:
        mid = table.names.index(new)
        guard_k = table.kn[mid] + table.ks[mid]
    w2 = frequency_bound(world.contacts, world.state, p)
    guard = np.zeros_like(w2)
    if guard_k is not None:
        kk = guard_k * p.radius
        guard = 2.0 * (kk / p.mass + kk * p.radius ** 2 / p.inertia)
        w2 = np.maximum(w2, guard)
    kt, kr = support.support_stiffness(cables, liners, p.mass.shape[0])
    w2 = w2 + 2.0 * (kt / p.mass + kr / p.inertia)
    moving = (p.active > 0) & (p.fixity != (FIX_X | FIX_Y | FIX_ROT)) & (w2 > 0)
    scale, target = _mass_scale(w2, moving, options.mass_scaling)
    w2 = w2 / scale
    p.inv_mass[:] = 1.0 / (p.mass * scale)
    p.inv_inertia[:] = 1.0 / (p.inertia * scale)
    w2max = float(w2[moving].max()) if moving.any() else 0.0
    if _eigen(options, world) and moving.any():
        w2max = _eigen_omega2(world, moving, guard / scale,
                              (kt / p.mass + kr / p.inertia) / scale)
    if not zone_kernels.is_empty(world.zones):
        w2max = max(w2max, _zone_frequency(world, target, options.mass_scaling))
    if w2max == 0 and support.has_nodes(cables, liners) and np.any(w2[p.active > 0] > 0):
        w2max = float(w2[p.active > 0].max())     # only the support moves
    _check_representable(w2max, table, support.has_nodes(cables, liners))
    if w2max > 0:
        support.set_node_masses(cables, liners, w2max)
    critical = 2.0 / math.sqrt(w2max) if w2max > 0 else math.inf
    if options.dt is not None:
        return TimeStep(float(options.dt), critical)
    if math.isfinite(critical):
        return TimeStep(options.safety * critical, critical)
    return TimeStep(previous_dt, critical)      # no contacts yet: cycle() asks for a dt


def _check_representable(w2max, table, has_support) -> None:
    """ValueError when omega_max^2 (1/s^2) is not a finite number whose step 2 / omega_max is
    above 0: a stiffness (Pa/m) so large over the blocks' masses that the step under- or
    overflows (e.g. kn = 1e308), named with the stiffest material."""
    if math.isfinite(w2max) and (w2max == 0 or 2.0 / math.sqrt(w2max) > 0):
        return
    k = int(np.argmax(table.kn + table.ks))
    raise ValueError(
        f"no time step can be computed: omega_max^2 = {w2max:.3g} 1/s^2 from the contact "
        f"stiffness over the blocks' masses; the stiffest material is {table.names[k]!r} "
        f"(kn = {table.kn[k]:.3g}, ks = {table.ks[k]:.3g} Pa/m)"
        + (", or a cable's or liner's stiffness" if has_support else "")
        + ": a contact stiffness is about E / block size, 1e4 to 1e17 Pa/m")


def _eigen(options, world) -> bool:
    """Whether the step comes from the largest eigenvalue: "eigen", or "auto" on rigid blocks
    (``critical_step`` has no zones)."""
    return options.step_estimate == "eigen" or (
        options.step_estimate == "auto" and zone_kernels.is_empty(world.zones))


def _mass_scale(w2, moving, mass_scaling):
    """(scale (nb,), target omega^2 or None): the inertial mass factor of each block."""
    if not (mass_scaling and moving.any()):
        return np.ones(w2.shape[0]), None
    target = float(np.median(w2[moving]))
    return np.maximum(1.0, w2 / target), target


def _eigen_omega2(world, moving, guard, support_w2):
    """omega_max^2 for ``step_estimate="eigen"``: the largest eigenvalue of the contacts
    (``critical_step``), at least the guard of any free block that has no contact, plus the
    support elements' own bound (Weyl: the largest eigenvalue of a sum is at most the sum of
    the largest ones). A block's contacts within the search margin are all listed, so a block
    that has some needs no guard: a contact that closes before the next search is already
    counted, and the search that adds one recomputes the step. ``guard``, ``support_w2``: per
    block, over the mass scale."""
    c = world.contacts
    alone = moving.copy()
    alone[c.block_a[:c.n]] = False
    alone[c.block_b[:c.n]] = False
    lam = critical_step.largest_omega2(c, world.state, world.props, world.corners)
    lone = float(guard[alone].max()) if alone.any() else 0.0
    return max(lam, lone) + 2.0 * float(support_w2[moving].max())


def _zone_frequency(world, target, mass_scaling):
    """The gridpoints' largest omega^2 (Gershgorin: zones plus 2 (kn + ks) L of the contacts
    each takes a share of, over its mass); with mass scaling (``target``, the blocks' median
    bound) a gridpoint above the target gets that much more inertial mass, as a block does
    (when no block is free, the zones' own median is the target)."""
    z, p = world.zones, world.props
    w2 = zone_kernels.gridpoint_stiffness(z, world.contacts, world.state) / z.mass
    live = np.repeat(p.active > 0, np.diff(z.point_offsets))
    if target is None and mass_scaling and live.any():
        target = float(np.median(w2[live]))       # no free block: the zones' own median
    scale = np.ones_like(w2) if target is None else np.maximum(1.0, w2 / target)
    z.inv_mass[:] = 1.0 / (z.mass * scale)
    return float((w2 / scale)[live].max()) if live.any() else 0.0
