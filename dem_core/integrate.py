"""Explicit time stepping: central differences (leapfrog) with local non-viscous damping.

One step (``run_steps`` loops this n times inside numba, no Python in between)::

    f = contact forces (+ servo velocities) (+ gravity) (+ applied loads)
    for each free velocity component:  F_d = f - alpha |f| sign(v)        (local damping)
                                       v  += F_d / m_inertial * dt
    prescribed components:             v   = v_bc
    x += v dt;  theta += omega dt

Velocities live at half steps (t - dt/2, t + dt/2), positions at whole steps. With alpha = 0 the
scheme is symplectic: energy oscillates by O((omega dt)^2) and does not drift.

Kinetic damping (``flags[4]`` = the check interval in steps, 0 = off; dynamic relaxation):
every that many steps the kinetic energy of the free velocity components (inertial masses) is
compared with the previous check; when it has fallen, the model has just passed a kinetic-energy
peak, i.e. its lowest active mode is near its static position, and every free velocity is set
to zero. The motion then restarts as leapfrog starts from rest: the first velocity update after
the stop is half a step (v = a dt/2), which makes the stopped position a turning point of every
mode. A plain v = 0 (the first update a full step) puts the turning point half a step earlier,
so each stop would start every fast mode with its amplitude divided by cos(omega dt/2), up to
14 % at the safety factor 0.5; because stops come when the kinetic energy is low, i.e. with the
fast modes near their turning points, that gain compounded into a growing block-scale rattle
(the Longtan conventional run, docs/mechanics.md).
(Checking every step would react to the step-to-step flicker of the many fast modes
and freeze the model; the interval must stay well below a quarter of the slowest period.) Local damping converges a slender model's
lowest bending mode only over many of its periods (it becomes a slow creep); kinetic damping
stops it near the static state within a few quarter periods. Prescribed velocities are kept.

Run status codes: 0 done, 1 a block moved more than half the search margin since the last
contact search (the driver searches and continues), 2 unstable (NaN, or a block moving more than
a tenth of its radius, or turning 0.1 rad, in one step; ``bad`` names the block).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .forces import add_contact_forces, add_gravity, add_loads, servo_velocities
from .parallel import add_contact_forces_parallel

__all__ = ["run_steps", "update_rotation", "frequency_bound", "free_kinetic_energy",
           "stop_free_motion", "DONE", "NEED_SEARCH", "UNSTABLE"]

DONE, NEED_SEARCH, UNSTABLE = 0, 1, 2


@njit(cache=True)
def update_rotation(theta, rot):
    for i in range(theta.shape[0]):
        rot[i, 0] = math.cos(theta[i])
        rot[i, 1] = math.sin(theta[i])


@njit(cache=True)
def _damped(f, v, alpha):
    if alpha > 0.0 and v != 0.0:
        return f - alpha * abs(f) * (1.0 if v > 0.0 else -1.0)
    return f


@njit(cache=True)
def advance(f, pos, theta, vel, omega, inv_mass, inv_inertia, fixity, velocity_bc, active,
            radius, pos_search, theta_search, alpha, dt, half_margin, kick=-1.0):
    """Damp, integrate and check every block; returns (status, block).

    ``kick`` (s): the time of the velocity update, default ``dt`` (``dt / 2`` on the first step
    after a kinetic-damping stop, see the module docstring); positions always move by v dt.
    """
    if kick < 0.0:
        kick = dt
    status, bad = 0, -1
    for i in range(pos.shape[0]):
        if not active[i]:
            continue
        fx = fixity[i]
        if fx & 1:
            vel[i, 0] = velocity_bc[i, 0]
        else:
            vel[i, 0] += _damped(f[i, 0], vel[i, 0], alpha) * inv_mass[i] * kick
        if fx & 2:
            vel[i, 1] = velocity_bc[i, 1]
        else:
            vel[i, 1] += _damped(f[i, 1], vel[i, 1], alpha) * inv_mass[i] * kick
        if fx & 4:
            omega[i] = velocity_bc[i, 2]
        else:
            omega[i] += _damped(f[i, 2], omega[i], alpha) * inv_inertia[i] * kick
        step = math.hypot(vel[i, 0], vel[i, 1]) * dt
        turn = abs(omega[i]) * dt
        if not (step <= 0.1 * radius[i] and turn <= 0.1):   # also catches NaN
            return 2, i
        pos[i, 0] += vel[i, 0] * dt
        pos[i, 1] += vel[i, 1] * dt
        theta[i] += omega[i] * dt
        moved = (math.hypot(pos[i, 0] - pos_search[i, 0], pos[i, 1] - pos_search[i, 1])
                 + abs(theta[i] - theta_search[i]) * radius[i])
        if moved > half_margin:
            status, bad = 1, i
    return status, bad


@njit(cache=True)
def free_kinetic_energy(vel, omega, inv_mass, inv_inertia, fixity, active):
    """1/2 sum m v^2 + I w^2 over free velocity components, inertial (scaled) masses, J/m."""
    ke = 0.0
    for i in range(vel.shape[0]):
        if not active[i]:
            continue
        fx = fixity[i]
        if inv_mass[i] > 0.0:
            if not fx & 1:
                ke += vel[i, 0] * vel[i, 0] / inv_mass[i]
            if not fx & 2:
                ke += vel[i, 1] * vel[i, 1] / inv_mass[i]
        if inv_inertia[i] > 0.0 and not fx & 4:
            ke += omega[i] * omega[i] / inv_inertia[i]
    return 0.5 * ke


@njit(cache=True)
def stop_free_motion(vel, omega, fixity, active):
    """Zero every free velocity component (prescribed ones keep their value)."""
    for i in range(vel.shape[0]):
        if not active[i]:
            continue
        fx = fixity[i]
        if not fx & 1:
            vel[i, 0] = 0.0
        if not fx & 2:
            vel[i, 1] = 0.0
        if not fx & 4:
            omega[i] = 0.0


@njit(cache=True)
def run_steps(nsteps, time, dt, alpha, half_margin, gravity, flags,
              pos, theta, vel, omega, force, rot, pos_search, theta_search,
              mass, inv_mass, inv_inertia, radius, fixity, velocity_bc, load, active,
              nc, block_a, block_b, point_a, point_b, normal_b, length, kn, ks, material,
              sn, ts, un, us, up, broken, slipping, strength, cracks, crack_count,
              servo_offsets, servo_blocks, servo_params, ke_last, work=None, events=None,
              table_offsets=None, table_entries=None):
    """Advance up to ``nsteps`` steps; returns (steps done, time, status, block).

    ``flags`` = [has_gravity, has_loads, has_servo, check_search, kinetic_interval] (int64
    array); ``ke_last`` (3,) holds, for kinetic damping, the kinetic energy at the previous
    check (J/m, inertial masses), the steps since it and 1 when the motion was just stopped
    (the next velocity update is half a step); updated in place. Stops early
    with status 1 (search needed, after completing the step) or 2 (unstable, before moving).
    With the scratch ``work``/``events`` and the block -> contact table given, the contact
    forces run on several threads (``parallel.add_contact_forces_parallel``, same results).
    """
    for step in range(nsteps):
        force[:] = 0.0
        if work is None:
            add_contact_forces(nc, block_a, block_b, point_a, point_b, normal_b, length, kn,
                               ks, material, strength, sn, ts, un, us, up, broken, slipping,
                               pos, rot, force, time, cracks, crack_count)
        else:
            add_contact_forces_parallel(nc, block_a, block_b, point_a, point_b, normal_b,
                                        length, kn, ks, material, strength, sn, ts, un, us, up,
                                        broken, slipping, pos, rot, force, time, cracks,
                                        crack_count, work, events, table_offsets,
                                        table_entries)
        if flags[2]:
            servo_velocities(servo_offsets, servo_blocks, servo_params, force, velocity_bc)
        if flags[0]:
            add_gravity(mass, active, gravity, force)
        if flags[1]:
            add_loads(load, active, force)
        margin = half_margin if flags[3] else np.inf
        kick = 0.5 * dt if ke_last[2] != 0.0 else dt
        ke_last[2] = 0.0
        status, bad = advance(force, pos, theta, vel, omega, inv_mass, inv_inertia, fixity,
                              velocity_bc, active, radius, pos_search, theta_search, alpha, dt,
                              margin, kick)
        if status == 2:
            return step, time, 2, bad
        update_rotation(theta, rot)
        time += dt
        if flags[4] > 0:
            ke_last[1] += 1.0
            if ke_last[1] >= flags[4]:
                ke_last[1] = 0.0
                ke = free_kinetic_energy(vel, omega, inv_mass, inv_inertia, fixity, active)
                if ke < ke_last[0]:
                    stop_free_motion(vel, omega, fixity, active)
                    ke = 0.0
                    ke_last[2] = 1.0          # restart from rest: half a kick next step
                ke_last[0] = ke
        if status == 1:
            return step + 1, time, 1, bad
    return nsteps, time, 0, -1


@njit(cache=True)
def frequency_bound(nc, block_a, block_b, point_a, length, kn, ks, pos, rot, mass, inertia):
    """(nb,) upper bound of omega^2 per block: 2 (sum k L / m + sum k L r^2 / I), k = kn + ks.

    The factor 2 bounds the coupling to the neighbours (Gershgorin); the sum of kn and ks bounds
    both directions. The critical step of central differences is 2/omega_max.
    """
    nb = mass.shape[0]
    kt = np.zeros(nb)
    kr = np.zeros(nb)
    for k in range(nc):
        a, b = block_a[k], block_b[k]
        kk = (kn[k] + ks[k]) * length[k]
        ca, sa = rot[a, 0], rot[a, 1]
        x = pos[a, 0] + ca * point_a[k, 0] - sa * point_a[k, 1]
        y = pos[a, 1] + sa * point_a[k, 0] + ca * point_a[k, 1]
        kt[a] += kk
        kt[b] += kk
        kr[a] += kk * ((x - pos[a, 0]) ** 2 + (y - pos[a, 1]) ** 2)
        kr[b] += kk * ((x - pos[b, 0]) ** 2 + (y - pos[b, 1]) ** 2)
    return 2.0 * (kt / mass + kr / inertia)
