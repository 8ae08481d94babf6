"""Kinetic damping (dynamic relaxation) and the kick of the step after a stop.

Kinetic damping (dynamic relaxation, ``Integrator.kinetic_interval`` > 0): every that many steps
the kinetic energy of the free velocity components (inertial masses) is compared with the last
check; when it has fallen, the model has just passed a kinetic-energy peak, i.e. its lowest
active mode is near its static position, and every free velocity is set to zero. The motion
restarts as leapfrog starts from rest: the first velocity update after the stop is half a step
(v = a dt/2), which makes the stopped position a turning point of every mode (a plain v = 0
restart starts each fast mode with its amplitude divided by cos(omega dt/2): docs/history.md).
The interval must stay well below a quarter of the period of the mode that carries the kinetic
energy; local damping converges a slender model's lowest bending mode only over many of its
periods, kinetic damping within a few quarter periods. Prescribed velocities are kept.

Checks too sparse for the motion: when the peak falls between two checks, the stop comes late,
near the next minimum of the kinetic energy, takes almost nothing out, and the mode rings on
(the crest blocks of the Longtan slope rock at 5 cm/s through a whole level with every stop
late: docs/mechanics.md, "Kinetic damping"). A stop is *late* when its kinetic energy is below
``LATE_STOP`` (1/2) of the largest checked since the previous stop. With
``Integrator.kinetic_adaptive`` (the default) a late stop halves the check interval (down to 1
step); the interval goes back to ``kinetic_interval`` at the start of every solve
(``workflow.solve``: a new load step), so a slow mode is not stopped at every ripple of a fast
one. A mode whose energy period divides the interval is seen at one phase check after check,
never falls between two checks, and rings on unseen (a toe mode of the Longtan slope with a
25-step energy period against checks 25 steps apart); so the checks' spacing is spread over
[1/2, 1) of the interval by the golden ratio's sequence (spacing = interval x (1/2 + frac(i
phi) / 2) at the i-th check; deterministic, so a saved model resumes bit for bit). Without
``kinetic_adaptive`` the interval is fixed and not spread (the rule before 2026-11-30). The
memory ``Integrator.kinetic`` (8,): the kinetic energy at the last check (J/m), steps since it,
1 when the motion was just stopped, the largest energy checked since the last stop, the number
of stops and of late stops, the interval now (0: ``kinetic_interval``), the checks so far.

Everything that moves takes part: the blocks, the deformable blocks' gridpoints and the cable
and liner nodes count in the kinetic energy (inertial masses), and a stop zeroes all their
velocities; the half kick after it is the one kick of the step's integration
(``integration.advance``, ``integration.advance_nodes``).

Sources: kinetic damping is the dynamic relaxation of P. A. Cundall (1976), "Explicit finite
difference methods in geomechanics", Proc. 2nd Int. Conf. Numerical Methods in Geomechanics,
Blacksburg, ASCE, vol. 1, pp. 132-150, in the form set out by P. Underwood (1983), "Dynamic
relaxation", in T. Belytschko and T. J. R. Hughes (eds), Computational Methods for Transient
Analysis, North-Holland, ch. 5: an explicit dynamic solution run to its static limit,
stopping the motion at every peak of the kinetic energy.
"""
from __future__ import annotations

import math

from numba import njit

from ..deformable.component import zone_kinetic_energy
from .nodes import stop_support, support_kinetic_energy

# a stop whose kinetic energy is below this fraction of the largest checked since the last
# stop came after the peak, not at it (a sin^2 peak checked at most a sixth of its period late
# keeps 3/4 of its energy; half of it at an eighth of a period late)
LATE_STOP = 0.5
# Integrator.kinetic: the kinetic-damping memory (module docstring)
KE_LAST, SINCE_CHECK, HALF_KICK, KE_LARGEST, STOPS, LATE_STOPS, EVERY, CHECKS = range(8)
# the checks' spacing is spread over [1/2, 1) of the interval by the golden ratio's sequence,
# so that no mode is sampled at one phase check after check
GOLDEN = 0.6180339887498949

__all__ = ["next_kick", "end_step", "kinetic_damping", "free_kinetic_energy", "stop_free_motion"]


@njit(cache=True)
def next_kick(integ):
    """The time (s) of this step's velocity update: ``dt``, or ``dt / 2`` on the first step
    after a kinetic-damping stop (which this clears)."""
    kick = 0.5 * integ.dt if integ.kinetic[HALF_KICK] != 0.0 else integ.dt
    integ.kinetic[HALF_KICK] = 0.0
    return kick


@njit(cache=True)
def end_step(integ, world, parts):
    """Kinetic damping after everything moved: the blocks and ``world.zones`` and, unless
    ``parts`` is None (the threaded region's step: gravity only, no support), the support
    nodes of ``parts``."""
    kinetic_damping(integ, world.state, world.props, world.zones, parts)


@njit(cache=True)
def kinetic_damping(integ, s, p, zones, parts):
    """Every ``kinetic_interval`` steps: stop all free motion after a kinetic-energy peak
    (the blocks', the deformable blocks' gridpoints' (``zones``; None: rigid blocks, left
    out) and the support nodes' (``parts``; None: left out))."""
    if integ.kinetic_interval <= 0:
        return
    k = integ.kinetic
    k[SINCE_CHECK] += 1.0
    adapted = integ.kinetic_adaptive and k[EVERY] > 0.0
    every = k[EVERY] if adapted else float(integ.kinetic_interval)
    spread = 0.5 + 0.5 * ((k[CHECKS] * GOLDEN) % 1.0) if integ.kinetic_adaptive else 1.0
    if k[SINCE_CHECK] < max(1.0, math.floor(every * spread)):
        return
    k[SINCE_CHECK] = 0.0
    k[CHECKS] += 1.0
    ke = free_kinetic_energy(s, p)
    if zones is not None:
        ke += zone_kinetic_energy(zones, p.active)
    if parts is not None:
        ke += support_kinetic_energy(parts.cables, parts.liners)
    k[KE_LARGEST] = max(k[KE_LARGEST], ke)
    if ke < k[KE_LAST]:
        stop_free_motion(s, p, zones, parts)
        k[STOPS] += 1.0
        if ke < LATE_STOP * k[KE_LARGEST]:
            k[LATE_STOPS] += 1.0
            if integ.kinetic_adaptive:      # the peak fell between two checks: check twice as often
                k[EVERY] = max(1.0, math.floor(0.5 * every))
        k[KE_LARGEST] = 0.0
        ke = 0.0
        k[HALF_KICK] = 1.0          # restart from rest: half a kick next step
    k[KE_LAST] = ke


@njit(cache=True)
def free_kinetic_energy(s, p):
    """1/2 sum m v^2 + I w^2 over free velocity components, inertial (scaled) masses, J/m."""
    ke = 0.0
    for i in range(s.vel.shape[0]):
        if not p.active[i]:
            continue
        fx = p.fixity[i]
        if p.inv_mass[i] > 0.0:
            if not fx & 1:
                ke += s.vel[i, 0] * s.vel[i, 0] / p.inv_mass[i]
            if not fx & 2:
                ke += s.vel[i, 1] * s.vel[i, 1] / p.inv_mass[i]
        if p.inv_inertia[i] > 0.0 and not fx & 4:
            ke += s.omega[i] * s.omega[i] / p.inv_inertia[i]
    return 0.5 * ke


@njit(cache=True)
def stop_free_motion(s, p, zones, parts):
    """Zero every free velocity component (prescribed ones keep their value), and the
    gridpoints' (``zones``) and support nodes' (``parts``) velocities (None: left out)."""
    if zones is not None:
        zones.v[:] = 0.0
    if parts is not None:
        stop_support(parts.cables, parts.liners)
    for i in range(s.vel.shape[0]):
        if not p.active[i]:
            continue
        fx = p.fixity[i]
        # the energy account: the stop takes the kinetic energy out (inertial masses)
        if not fx & 1:
            if p.inv_mass[i] > 0.0:
                s.work[i, 1] += 0.5 * s.vel[i, 0] * s.vel[i, 0] / p.inv_mass[i]
            s.vel[i, 0] = 0.0
        if not fx & 2:
            if p.inv_mass[i] > 0.0:
                s.work[i, 1] += 0.5 * s.vel[i, 1] * s.vel[i, 1] / p.inv_mass[i]
            s.vel[i, 1] = 0.0
        if not fx & 4:
            if p.inv_inertia[i] > 0.0:
                s.work[i, 1] += 0.5 * s.omega[i] * s.omega[i] / p.inv_inertia[i]
            s.omega[i] = 0.0
