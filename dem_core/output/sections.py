"""Forces across a section: the resultant that one set of blocks exerts on another through
their contacts (per metre of thickness, plane strain).

A section is a cut between two sets of blocks, e.g. a layer cut across at a station along
it. For the contacts k between a block of ``side`` and a block of ``across``::

    F = sum_k  +-L_k (sn_k n_k + ts_k t_k)              N/m, on ``side``
    M = sum_k  (x_k - p) x F_k                          N m/m about p, counter-clockwise +

with n_k the contact's normal from A into B, t_k = (-n_y, n_x), the sign + where ``side``
holds B (the force on B is L (sn n + ts t), ``contact.contacts``) and - where it holds A, and
x_k the point the contact's force acts at (its anchor, ``contact.forces``). With N = F . a (a: the unit vector along the member, pointing into
``side``) the thrust is compression-positive, and where the resultant crosses the cut line
p + e m (m: the cut's unit direction) is e = M / (m x F).

On edge elements (``Model(edge_elements=True)``) each shared edge adds its element's share to
its two lumped forces (a couple where both ends are closed, the compressed part of the linear
field where one is open: ``contact.forces.edge_correction``), as the time step does; the
section adds it too, so F and M are the forces the blocks feel at this state.
"""
from __future__ import annotations

import numpy as np

from ..contact.forces import _force_point, edge_correction

__all__ = ["section_force", "thrust_line"]


def section_force(model, side, across, point) -> dict:
    """The resultant of the contact forces that blocks ``across`` exert on blocks ``side``.

    ``side``, ``across``: boolean masks over the blocks (disjoint); ``point`` (x, y), m: the
    moment's centre. Returns {"force": (fx, fy) N/m, "moment": N m/m about ``point``
    (counter-clockwise +), "contacts": how many contacts cross}."""
    side, across = np.asarray(side, bool), np.asarray(across, bool)
    if side.shape != across.shape or side.shape[0] != model.n_blocks:
        raise ValueError(f"section_force: side and across must be masks over the model's "
                         f"{model.n_blocks} blocks, got shapes {side.shape} and "
                         f"{across.shape}")
    if np.any(side & across):
        raise ValueError("section_force: side and across share blocks "
                         f"{np.flatnonzero(side & across)[:5].tolist()}")
    c, st = model.contacts, model.state
    a, b = c.live("block_a"), c.live("block_b")
    on_b = side[b] & across[a]
    rows = np.flatnonzero(on_b | (side[a] & across[b]))
    nrm = c.normal(st)[rows]
    tan = np.column_stack([-nrm[:, 1], nrm[:, 0]])
    load = c.live("length")[rows, None] * (c.live("sn")[rows, None] * nrm
                                           + c.live("ts")[rows, None] * tan)
    f = np.where(on_b[rows], 1.0, -1.0)[:, None] * load
    x = np.array([_force_point(int(k), c, st) for k in rows]).reshape(-1, 2)
    r = x - np.asarray(point, float)
    force = f.sum(axis=0)
    moment = float(np.sum(r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0]))
    if model.edge_elements:
        df, dm = _edge_shares(model, rows, x, side, point)
        force, moment = force + df, moment + dm
    return {"force": force, "moment": moment, "contacts": int(rows.size)}


def _edge_shares(model, rows, x, side, point) -> tuple:
    """The edge elements' shares among ``rows`` (each edge once: both halves join the same two
    blocks, so both cross): force on ``side`` (N/m) and its moment about ``point``. Computed
    by the step's own ``edge_correction``, with the contact state it updates put back."""
    c, st = model.contacts, model.state
    partner = c.live("partner")
    kept = {name: getattr(c, name).copy() for name in ("edge_x0", "ts", "work_friction")}
    force, moment = np.zeros(2), 0.0
    p0 = np.asarray(point, float)
    try:
        for i, k in enumerate(rows):
            if not 0 <= partner[k] < k:
                continue
            gx, gy, mb, ma = edge_correction(int(k), c, st, x[i, 0], x[i, 1])
            g = np.array([gx, gy])
            on, m_own, sign = ((c.block_b[k], mb, 1.0) if side[c.block_b[k]]
                               else (c.block_a[k], -ma, -1.0))
            r = st.pos[on, :2] - p0
            force += sign * g
            moment += m_own + sign * (r[0] * gy - r[1] * gx)
    finally:
        for name, arr in kept.items():
            getattr(c, name)[:] = arr
    return force, moment


def thrust_line(model, members, origin, along, normal, thickness, stations) -> dict:
    """Thrust, shear and thrust line of a member (a layer, a column) cut across at stations.

    ``members``: boolean mask of its blocks; ``origin`` (x, y), m: a point of its outer face
    line; ``along``: the unit direction of that line; ``normal``: the unit normal out of the
    member through that face (the member lies at depths 0..``thickness`` m along -normal).
    The cut at station s (m) separates the member's blocks whose centroid lies beyond s,
    ``(x - origin) . along > s`` (the far part), from the rest; its mid-point is
    ``p = origin + s along - thickness / 2 normal``. With F the force of the near part on the
    far part (``section_force``, moment M about p), per station:

        N = F . along        thrust, N/m, compression +
        V = F . normal       shear across the member, N/m
        e = M / (normal x F) where F crosses the cut line p + e normal, m (+ towards the face)

    Returns lists "N", "V", "e_over_t" (e / thickness: the section is -0.5..0.5, its kern
    -1/6..1/6) and "contacts" per station."""
    along = np.asarray(along, float) / np.hypot(*along)
    normal = np.asarray(normal, float) / np.hypot(*normal)
    members = np.asarray(members, bool)
    origin = np.asarray(origin, float)
    s_block = (model.state.pos[:, :2] - origin) @ along
    out = {"N": [], "V": [], "e_over_t": [], "contacts": []}
    for s in stations:
        far = members & (s_block > s)
        mid = origin + s * along - 0.5 * thickness * normal
        sec = section_force(model, far, members & ~far, mid)
        f = sec["force"]
        cross = float(normal[0] * f[1] - normal[1] * f[0])
        out["N"].append(float(f @ along))
        out["V"].append(float(f @ normal))
        out["e_over_t"].append(sec["moment"] / cross / thickness if abs(cross) > 1e-9
                               else float("nan"))
        out["contacts"].append(sec["contacts"])
    return out
