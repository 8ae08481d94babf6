"""Shotcrete liners: beam elements along a chain of exposed block faces, bonded to the rock.

A liner is a chain of nodes (x, y, rotation theta) at the ends of the pieces its exposed faces
are cut into; element e joins nodes a -> b, one per piece. Each piece is bonded to its face's
block by two bonds, one at each end node over half the piece's length. Per unit thickness (plane
strain, a liner is continuous out of plane): EA = E t, EI = E t^3 / 12 per metre.

Elements (Euler-Bernoulli, co-rotational): chord length L and angle beta; with
psi = beta - beta0 the chord's rotation, the end rotations relative to it are
phi = theta - psi and, elastic-perfectly plastic by the plastic elongation and hinge rotations
(``el_plastic``)::

    N   = EA / L0 (L - L0 - plastic_axial),          -n_c <= N <= n_t      (tension +)
    M_a = EI / L0 (4 phi_a' + 2 phi_b'),  M_b = EI / L0 (2 phi_a' + 4 phi_b'),
          phi' = phi - plastic_rotation,              |M| <= m_p
    V   = (M_a + M_b) / L

Node a gets N e - V e_y and moment -M_a, node b -N e + V e_y and -M_b (e the chord's unit
vector, e_y = e turned +90 degrees; CCW moments +).

Bond (per half piece of length l): the node's offset r from the host-face point it was
installed on, along the face's outward normal n (opening +) and along the face, and the node's
rotation relative to its host since installation::

    F_n = k_n l (r . n),  F_s = k_s l (r . t),  M = k_n l^3 / 3 (theta - theta_host)

(the springs of the half piece lumped at its end node: M is their moment about the node); the
node gets -(F_n n + F_s t) and -M, the host the opposite. The bond breaks for good when its
peak normal stress F_n / l + 6 |M| / l^2 exceeds its tensile strength or |F_s| / l its shear
strength; afterwards the face only pushes (F_n for r . n < 0; no shear, no moment), and only
while the node is over that bond's own bit of face (|r . t| and -r . n at most l): once the
block has moved or turned away, its face's line no longer reaches the node (without that limit
a turned face could find the node metres "inside" it and throw it out: docs/history.md). A bond
whose host was excavated is gone, so a liner spans the opening. Gravity (the step's
``Gravity`` bundle) acts on the liner's real mass rho t l per node; its inertia is scaled like
a cable node's (``support.set_node_masses``).

This kernel computes forces only (``add_liners``: elements, bonds, the nodes' weight). The
nodes (position and rotation) are advanced by the step's one integration
(``step.integration.advance_nodes``, ``step.nodes.advance_support``), right after the blocks
and with their dt, local damping, kick and kinetic-damping stop.

Events (first axial yield or hinge of an element, bond failure of a node) go to ``log_rows``
(``cables.log_event``; kinds ``YIELD`` and ``LINER_BOND``).
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..step.kinematics import body_point, rotate
from .cables import LINER_BOND, YIELD, log_event

__all__ = ["Liners", "add_liners", "no_liners"]


class Liners(NamedTuple):
    """Every liner of a model (``N`` nodes, ``E`` elements; both 0: none).

    node_pos : (N, 2) m. node_theta : (N,) rad. node_vel : (N, 2) m/s. node_omega : (N,) rad/s.
    node_force : (N, 3) N/m, N m/m (scratch). node_pos0 : (N, 2) m, where each node was
    installed. node_mass : (N,) kg/m real. node_inv_mass,
    node_inv_inertia : (N,) inertial. node_liner : (N,) int64.
    bond_node, bond_host : (B,) int64. bond_local, bond_normal : (B, 2) the host point (m) and
        the face's outward normal, host body frame. bond_theta0 : (B,) host rotation at
        installation (rad). bond_length : (B,) m (half a piece). bond_kn, bond_ks : (B,) N/m
        per m (stiffness x length). bond_kr : (B,) N m/rad per m. bond_tension, bond_shear :
        (B,) Pa. bond_state : (B,) int8 (1 broken). bond_force : (B, 3) normal (+: the bond
        pulls the liner to the rock), shear (N/m), moment (N m/m).
    el_a, el_b : (E,) int64. el_length0, el_angle0 : (E,) m, rad. el_ea, el_ei : (E,) N/m per
        m... (N, N m^2 per m). el_nt, el_nc : (E,) N/m axial yield (>= 0). el_mp : (E,) N m/m.
    el_plastic : (E, 3) axial (m), hinge rotations at a, b (rad). el_force : (E, 3) N, M_a, M_b.
    el_state : (E,) int8, 1 once yielded. el_liner : (E,) int64.
    log_rows : (cap, 7), log_count : (1,) (``cables`` module docstring).
    """

    node_pos: np.ndarray
    node_theta: np.ndarray
    node_vel: np.ndarray
    node_omega: np.ndarray
    node_force: np.ndarray
    node_pos0: np.ndarray
    node_mass: np.ndarray
    node_inv_mass: np.ndarray
    node_inv_inertia: np.ndarray
    node_liner: np.ndarray
    bond_node: np.ndarray
    bond_host: np.ndarray
    bond_local: np.ndarray
    bond_normal: np.ndarray
    bond_theta0: np.ndarray
    bond_length: np.ndarray
    bond_kn: np.ndarray
    bond_ks: np.ndarray
    bond_kr: np.ndarray
    bond_tension: np.ndarray
    bond_shear: np.ndarray
    bond_state: np.ndarray
    bond_force: np.ndarray
    el_a: np.ndarray
    el_b: np.ndarray
    el_length0: np.ndarray
    el_angle0: np.ndarray
    el_ea: np.ndarray
    el_ei: np.ndarray
    el_nt: np.ndarray
    el_nc: np.ndarray
    el_mp: np.ndarray
    el_plastic: np.ndarray
    el_force: np.ndarray
    el_state: np.ndarray
    el_liner: np.ndarray
    log_rows: np.ndarray
    log_count: np.ndarray


_INT = {"bond_node", "bond_host", "node_liner", "el_a", "el_b", "el_liner", "log_count"}
_INT8 = {"bond_state", "el_state"}
_WIDTH = {"node_pos": 2, "node_pos0": 2, "node_vel": 2, "node_force": 3, "bond_local": 2,
          "bond_normal": 2, "bond_force": 3, "el_plastic": 3, "el_force": 3}


def no_liners() -> Liners:
    """The empty bundle."""
    out = {}
    for f in Liners._fields:
        dtype = np.int64 if f in _INT else np.int8 if f in _INT8 else np.float64
        out[f] = np.zeros((0, _WIDTH[f]) if f in _WIDTH else (0,), dtype)
    out["log_rows"] = np.zeros((64, 7))
    out["log_count"] = np.zeros(1, np.int64)
    return Liners(**out)


@njit(cache=True, inline="always")
def _wrap(a):
    """a in (-pi, pi]."""
    return a - 2.0 * math.pi * math.floor((a + math.pi) / (2.0 * math.pi))


@njit(cache=True)
def _elements(ln, time):
    """Beam element forces into node_force (module docstring; ``time`` s, for the event
    log)."""
    x, th, f = ln.node_pos, ln.node_theta, ln.node_force
    for e in range(ln.el_a.shape[0]):
        a, b = ln.el_a[e], ln.el_b[e]
        dx, dy = x[b, 0] - x[a, 0], x[b, 1] - x[a, 1]
        length = math.sqrt(dx * dx + dy * dy)
        ex, ey = dx / length, dy / length
        psi = _wrap(math.atan2(dy, dx) - ln.el_angle0[e])
        l0, pl = ln.el_length0[e], ln.el_plastic[e]
        n = ln.el_ea[e] / l0 * (length - l0 - pl[0])
        if n > ln.el_nt[e] or n < -ln.el_nc[e]:
            cap = ln.el_nt[e] if n > 0.0 else -ln.el_nc[e]
            pl[0] = length - l0 - cap * l0 / ln.el_ea[e]
            n = cap
            _yielded(ln, e, x, a, b, time)
        kb = ln.el_ei[e] / l0
        pa, pb = th[a] - psi - pl[1], th[b] - psi - pl[2]
        ma, mb = kb * (4.0 * pa + 2.0 * pb), kb * (2.0 * pa + 4.0 * pb)
        mp = ln.el_mp[e]
        if abs(ma) > mp or abs(mb) > mp:        # a hinge: the excess turns into plastic rotation
            if abs(ma) > mp:
                pl[1] += (ma - math.copysign(mp, ma)) / (4.0 * kb)
            if abs(mb) > mp:
                pl[2] += (mb - math.copysign(mp, mb)) / (4.0 * kb)
            pa, pb = th[a] - psi - pl[1], th[b] - psi - pl[2]
            ma = min(mp, max(-mp, kb * (4.0 * pa + 2.0 * pb)))
            mb = min(mp, max(-mp, kb * (2.0 * pa + 4.0 * pb)))
            _yielded(ln, e, x, a, b, time)
        v = (ma + mb) / length
        ln.el_force[e, 0], ln.el_force[e, 1], ln.el_force[e, 2] = n, ma, mb
        f[a, 0] += n * ex + v * ey
        f[a, 1] += n * ey - v * ex
        f[a, 2] -= ma
        f[b, 0] -= n * ex + v * ey
        f[b, 1] -= n * ey - v * ex
        f[b, 2] -= mb


@njit(cache=True, inline="always")
def _yielded(ln, e, x, a, b, time):
    if ln.el_state[e] == 0:
        ln.el_state[e] = 1
        log_event(ln.log_rows, ln.log_count, time, 0.5 * (x[a, 0] + x[b, 0]),
                  0.5 * (x[a, 1] + x[b, 1]), YIELD, ln.el_liner[e], e)


@njit(cache=True)
def _bond(ln, s, p, time, gravity):
    """Gravity (``gravity.accel``, m/s^2; no rows: none) on the nodes, and the bond forces
    between nodes and host faces (module docstring; ``time`` s, for the event log)."""
    x, f = ln.node_pos, ln.node_force
    for r in range(gravity.accel.shape[0]):
        gx, gy = gravity.accel[r, 0], gravity.accel[r, 1]
        for i in range(x.shape[0]):
            f[i, 0] += ln.node_mass[i] * gx
            f[i, 1] += ln.node_mass[i] * gy
    for k in range(ln.bond_node.shape[0]):
        h, i = ln.bond_host[k], ln.bond_node[k]
        if p.active[h] == 0:
            ln.bond_force[k, 0] = ln.bond_force[k, 1] = ln.bond_force[k, 2] = 0.0
            continue
        xh, yh = body_point(s.pos, s.rot, h, ln.bond_local[k, 0], ln.bond_local[k, 1])
        nx, ny = rotate(s.rot, h, ln.bond_normal[k, 0], ln.bond_normal[k, 1])
        rx, ry = x[i, 0] - xh, x[i, 1] - yh
        fn = ln.bond_kn[k] * (rx * nx + ry * ny)
        fs = ln.bond_ks[k] * (-rx * ny + ry * nx)
        m = ln.bond_kr[k] * (ln.node_theta[i] - (s.theta[h] - ln.bond_theta0[k]))
        length = ln.bond_length[k]
        if ln.bond_state[k] == 0 and (fn / length + 6.0 * abs(m) / length ** 2 >
                                      ln.bond_tension[k] or abs(fs) > ln.bond_shear[k] * length):
            ln.bond_state[k] = 1
            log_event(ln.log_rows, ln.log_count, time, x[i, 0], x[i, 1], LINER_BOND,
                      ln.node_liner[i], k)
        if ln.bond_state[k] != 0:          # only a push, and only over its own bit of face
            over = (abs(-rx * ny + ry * nx) <= length
                    and -(rx * nx + ry * ny) <= length)
            fn, fs, m = (min(fn, 0.0) if over else 0.0), 0.0, 0.0
        gxn = fn * nx - fs * ny                 # the pull on the node is -(gxn, gyn)
        gyn = fn * ny + fs * nx
        ln.bond_force[k, 0], ln.bond_force[k, 1], ln.bond_force[k, 2] = fn, fs, m
        f[i, 0] -= gxn
        f[i, 1] -= gyn
        f[i, 2] -= m
        s.force[h, 0] += gxn
        s.force[h, 1] += gyn
        s.force[h, 2] += (xh - s.pos[h, 0]) * gyn - (yh - s.pos[h, 1]) * gxn + m


@njit(cache=True)
def add_liners(ln, s, p, time, gravity):
    """Liner forces: the elements' and bonds' and the weight (``gravity``, the step's
    ``Gravity`` bundle) on the nodes (``node_force``), the bonds' on the host blocks; ``time``
    (s) the step's, for the event log. The nodes do not move here
    (``step.nodes.advance_support``)."""
    if ln.node_pos.shape[0] == 0:
        return
    ln.node_force[:] = 0.0
    _elements(ln, time)
    _bond(ln, s, p, time, gravity)
