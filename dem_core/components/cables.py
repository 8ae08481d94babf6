"""Grouted cables and rock bolts (UDEC's cable element): axial segments between nodes, each node
held in its hole by grout.

A cable is a chain of nodes (collar first); segment j joins nodes a -> b. Per unit thickness
(plane strain): every force is the cable's force divided by its out-of-plane spacing, N/m.

Axial (tension +), elastic-perfectly plastic, by the plastic elongation ``seg_plastic``::

    F = k (L - L0 - plastic),   -F_c <= F <= F_y   (k = E A / (L0 spacing))

a segment whose total strain (L - L0) / L0 passes its rupture strain breaks for good (F = 0).
Node a gets +F e, node b -F e (e the unit vector a -> b): a cable in tension pulls its ends in.

Grout (per node, over its tributary length): the node's offset r = x_node - x_host from the
host block's point it was installed on, less the grout's plastic offset r_p (a vector, world
frame), split along the cable's local axis t (the mean of the adjacent segments' directions)
and across it (n)::

    e = r - r_p
    F_axial = k_g (e . t),  |F_axial| <= cap   (perfectly plastic: r_p grows along t)
    F_across = k_g (e . n)                     (elastic: the node stays in its hole)

The plastic offset is a vector so that the grout's elastic energy k_g |e|^2 / 2 does not depend
on the axis: when the axis turns (the cable bends where blocks part), a slip already made along
the old axis stays slip, and is not turned into an elastic offset across the new one (a scalar
slip along the current axis did that, and fed energy into a cracking slope:
docs/history.md).

The grout pulls the node by -(F_axial t + F_across n) and the host block by the opposite, at
the host point (so momentum is conserved). A node whose host was excavated is free.

This kernel computes forces only (``add_cables``: the segments' axial forces and the grout's,
into ``node_force`` and onto the host blocks). The nodes are advanced by the step's one
integration (``step.integration.advance_nodes``, ``step.nodes.advance_support``), right after
the blocks and with their dt, local damping, kick and kinetic-damping stop: their inertial mass
is chosen when the time step is (``support.set_node_masses``) so that a node is no stiffer than
the stiffest block and the automatic step stays stable; the weight of a cable is left out (a
few kg per metre against the rock it holds).

Events (first grout slip of a node, first yield and rupture of a segment) go to ``log_rows``
like cracks: [time s, x m, y m, kind (``GROUT_SLIP``, ``YIELD``, ``RUPTURE``), cable, node or
segment, 0].
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..step.kinematics import body_point

__all__ = ["Cables", "add_cables", "no_cables", "GROUT_SLIP", "YIELD", "RUPTURE", "LINER_BOND",
           "log_event"]

# Event kinds of the support logs (cables and liners share the numbering).
GROUT_SLIP, YIELD, RUPTURE, LINER_BOND = 11, 12, 13, 14


class Cables(NamedTuple):
    """Every cable of a model (``N`` nodes, ``S`` segments; both 0: no cables).

    node_pos, node_vel : (N, 2) float64, m and m/s. node_force : (N, 2) N/m (scratch).
    node_pos0 : (N, 2) m, where each node was installed.
    node_tangent : (N, 2) scratch. node_axis : (N, 2) the axis at installation (unit).
    node_host : (N,) int64 block holding the node (-1: none). node_local : (N, 2) m, the host
        point in the host's body frame.
    grout_k : (N,) N/m per m, grout stiffness x tributary length / spacing.
    grout_cap : (N,) N/m, grout strength x tributary length / spacing (inf: a face plate;
        0: free length). grout_plastic : (N, 2) m, the plastic offset r_p (world frame).
        grout_force : (N,) N/m axial, on the cable.
    node_state : (N,) int8, 1 once the grout slipped. node_inv_mass : (N,) 1/(kg/m) inertial.
    node_cable : (N,) int64 cable index.
    seg_a, seg_b : (S,) int64 nodes. seg_length0 : (S,) m. seg_k : (S,) N/m per m.
    seg_yield_t, seg_yield_c : (S,) N/m, axial yield in tension and compression (both >= 0).
    seg_rupture : (S,) strain. seg_plastic : (S,) m. seg_force : (S,) N/m, tension +.
    seg_state : (S,) int8, 0 elastic, 1 yielded, 2 ruptured. seg_cable : (S,) int64.
    log_rows : (cap, 7) float64, log_count : (1,) int64: events (module docstring).
    """

    node_pos: np.ndarray
    node_vel: np.ndarray
    node_force: np.ndarray
    node_pos0: np.ndarray
    node_tangent: np.ndarray
    node_axis: np.ndarray
    node_host: np.ndarray
    node_local: np.ndarray
    grout_k: np.ndarray
    grout_cap: np.ndarray
    grout_plastic: np.ndarray
    grout_force: np.ndarray
    node_state: np.ndarray
    node_inv_mass: np.ndarray
    node_cable: np.ndarray
    seg_a: np.ndarray
    seg_b: np.ndarray
    seg_length0: np.ndarray
    seg_k: np.ndarray
    seg_yield_t: np.ndarray
    seg_yield_c: np.ndarray
    seg_rupture: np.ndarray
    seg_plastic: np.ndarray
    seg_force: np.ndarray
    seg_state: np.ndarray
    seg_cable: np.ndarray
    log_rows: np.ndarray
    log_count: np.ndarray

    @staticmethod
    def fields_of_old_files(held) -> dict:
        """A model file from before the vector plastic offset holds a scalar slip along the
        axis: taken along each node's installation axis (``io``)."""
        if "grout_slip" not in held:
            return {}
        return {"grout_plastic": held["grout_slip"][:, None] * held["node_axis"]}


_INT = {"node_host", "node_cable", "seg_a", "seg_b", "seg_cable", "log_count"}
_INT8 = {"node_state", "seg_state"}
_PAIRS = {"node_pos", "node_vel", "node_force", "node_pos0", "node_tangent", "node_axis",
          "node_local", "grout_plastic"}


def no_cables() -> Cables:
    """The empty bundle."""
    out = {}
    for f in Cables._fields:
        dtype = np.int64 if f in _INT else np.int8 if f in _INT8 else np.float64
        shape = (0, 2) if f in _PAIRS else (0,)
        out[f] = np.zeros(shape, dtype)
    out["log_rows"] = np.zeros((64, 7))
    out["log_count"] = np.zeros(1, np.int64)
    return Cables(**out)


@njit(cache=True, inline="always")
def log_event(rows, count, time, x, y, kind, element, part):
    k = count[0]
    if k < rows.shape[0]:
        rows[k, 0], rows[k, 1], rows[k, 2], rows[k, 3] = time, x, y, kind
        rows[k, 4], rows[k, 5], rows[k, 6] = element, part, 0.0
    count[0] = k + 1


@njit(cache=True)
def _axial(cb, time):
    """Segment forces into node_force; each segment's direction into node_tangent (``time``
    s: the step's, for the event log)."""
    x, f, t = cb.node_pos, cb.node_force, cb.node_tangent
    for j in range(cb.seg_a.shape[0]):
        if cb.seg_state[j] == 2:
            continue
        a, b = cb.seg_a[j], cb.seg_b[j]
        dx, dy = x[b, 0] - x[a, 0], x[b, 1] - x[a, 1]
        length = math.sqrt(dx * dx + dy * dy)
        ex, ey = dx / length, dy / length
        t[a, 0] += ex
        t[a, 1] += ey
        t[b, 0] += ex
        t[b, 1] += ey
        k, l0 = cb.seg_k[j], cb.seg_length0[j]
        force = k * (length - l0 - cb.seg_plastic[j])
        if force > cb.seg_yield_t[j] or force < -cb.seg_yield_c[j]:
            cap = cb.seg_yield_t[j] if force > 0.0 else -cb.seg_yield_c[j]
            cb.seg_plastic[j] = length - l0 - cap / k
            force = cap
            if cb.seg_state[j] == 0:
                cb.seg_state[j] = 1
                log_event(cb.log_rows, cb.log_count, time, 0.5 * (x[a, 0] + x[b, 0]),
                          0.5 * (x[a, 1] + x[b, 1]), YIELD, cb.seg_cable[j], j)
        if length - l0 > cb.seg_rupture[j] * l0:
            cb.seg_state[j] = 2
            force = 0.0
            log_event(cb.log_rows, cb.log_count, time, 0.5 * (x[a, 0] + x[b, 0]),
                      0.5 * (x[a, 1] + x[b, 1]), RUPTURE, cb.seg_cable[j], j)
        cb.seg_force[j] = force
        f[a, 0] += force * ex
        f[a, 1] += force * ey
        f[b, 0] -= force * ex
        f[b, 1] -= force * ey


@njit(cache=True)
def _grout(cb, s, p, time):
    """Grout forces between each node and its host block (module docstring; ``time`` s, for
    the event log)."""
    x, f, t = cb.node_pos, cb.node_force, cb.node_tangent
    for i in range(x.shape[0]):
        h = cb.node_host[i]
        if h < 0 or p.active[h] == 0:
            cb.grout_force[i] = 0.0
            continue
        tx, ty = t[i, 0], t[i, 1]
        norm = math.sqrt(tx * tx + ty * ty)
        if norm > 0.0:
            tx, ty = tx / norm, ty / norm
        else:                                   # every adjacent segment ruptured
            tx, ty = cb.node_axis[i, 0], cb.node_axis[i, 1]
        xh, yh = body_point(s.pos, s.rot, h, cb.node_local[i, 0], cb.node_local[i, 1])
        rp = cb.grout_plastic
        rx, ry = x[i, 0] - xh - rp[i, 0], x[i, 1] - yh - rp[i, 1]
        k = cb.grout_k[i]
        along = k * (rx * tx + ry * ty)
        cap = cb.grout_cap[i]
        if abs(along) > cap:               # the excess along the axis becomes plastic offset
            sign = 1.0 if along > 0.0 else -1.0
            excess = rx * tx + ry * ty - sign * cap / k
            rp[i, 0] += excess * tx
            rp[i, 1] += excess * ty
            rx -= excess * tx
            ry -= excess * ty
            along = sign * cap
            if cb.node_state[i] == 0 and cap > 0.0:
                cb.node_state[i] = 1
                log_event(cb.log_rows, cb.log_count, time, x[i, 0], x[i, 1], GROUT_SLIP,
                          cb.node_cable[i], i)
        across = k * (-rx * ty + ry * tx)
        gx = along * tx - across * ty
        gy = along * ty + across * tx
        cb.grout_force[i] = along
        f[i, 0] -= gx
        f[i, 1] -= gy
        s.force[h, 0] += gx
        s.force[h, 1] += gy
        s.force[h, 2] += (xh - s.pos[h, 0]) * gy - (yh - s.pos[h, 1]) * gx


@njit(cache=True)
def add_cables(cb, s, p, time):
    """Cable forces: the segments' and the grout's on the nodes (``node_force``), the grout's
    on the host blocks (module docstring); ``time`` (s) the step's, for the event log. The
    nodes do not move here (``step.nodes.advance_support``)."""
    if cb.node_pos.shape[0] == 0:
        return
    cb.node_force[:] = 0.0
    cb.node_tangent[:] = 0.0
    _axial(cb, time)
    _grout(cb, s, p, time)
