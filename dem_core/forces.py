"""Contact forces: each contact's geometry (``contacts.py``), its law (``law.py``) and the
force it adds to its two blocks. Forces go into ``BlockState.force`` ((nb, 3): fx, fy in N/m,
moment in N m/m, CCW +).
"""
from __future__ import annotations

import warnings

from numba import njit
from numba.core.errors import NumbaPerformanceWarning

from .contacts import ANCHOR_A, ANCHOR_B
from .kinematics import body_point, contact_normal, unrotate
from .law import coulomb_law

__all__ = ["add_contact_forces", "contact_update", "log_crack"]


@njit(cache=True, inline="always")
def contact_update(k, c, strength, s):
    """Contact k of ``c`` (Contacts) at the blocks' pose ``s`` (BlockState): updates its
    displacements and stresses and returns (fx, fy, xa, ya, event): the force on B (N/m; minus
    it on A), the point it acts at (m: A's vertex, or midway between the two faces' points of
    a face contact) and the law's event (1 tension failure, 2 shear failure,
    3 slip, 4 open). Shared by the serial kernel below and the threaded one (``parallel.py``),
    so both compute the same numbers."""
    a = c.block_a[k]
    b = c.block_b[k]
    xa, ya = body_point(s.pos, s.rot, a, c.point_a[k, 0], c.point_a[k, 1])
    xb, yb = body_point(s.pos, s.rot, b, c.point_b[k, 0], c.point_b[k, 1])
    nx, ny = contact_normal(s, a, b, c.face[k], c.normal_b[k, 0], c.normal_b[k, 1])
    u_n = (xb - xa) * nx + (yb - ya) * ny
    u_s = (yb - ya) * nx - (xb - xa) * ny
    s_n, t_s, sn_e, slip, event = coulomb_law(u_n - c.un[k], u_s - c.us[k], c.sn_elastic[k],
                                              c.ts[k], c.kn[k], c.ks[k], strength,
                                              c.material[k], c.broken[k])
    c.sn[k] = s_n
    c.ts[k] = t_s
    c.sn_elastic[k] = sn_e
    c.un[k] = u_n
    c.us[k] = u_s
    c.slipping[k] = 1 if (event == 2 or event == 3) else 0
    if event != 0:                         # (rare: the elastic path writes no more than this)
        c.up[k] += slip
        if event == 1 or event == 2:
            c.broken[k] = event
        _reanchor(k, c, s, xa, ya, xb, yb, u_n, nx, ny)
    # the point the force acts at
    anchor = c.anchor[k]
    px = xa if anchor == ANCHOR_A else (xb if anchor == ANCHOR_B else 0.5 * (xa + xb))
    py = ya if anchor == ANCHOR_A else (yb if anchor == ANCHOR_B else 0.5 * (ya + yb))
    L = c.length[k]
    return L * (s_n * nx - t_s * ny), L * (s_n * ny + t_s * nx), px, py, event


@njit(cache=True)        # not inlined: rare (slip or opening), kept out of the hot loop's code
def _reanchor(k, c, s, xa, ya, xb, yb, u_n, nx, ny):
    """Move the free point(s) of slipping or open contact k across the normal from its anchor
    (x_b - x_a = u_n n, so the tangential offset is zero again)."""
    anchor = c.anchor[k]
    if anchor == ANCHOR_A:
        px, py = xa, ya
    elif anchor == ANCHOR_B:
        px, py = xb - u_n * nx, yb - u_n * ny
    else:
        px, py = 0.5 * (xa + xb - u_n * nx), 0.5 * (ya + yb - u_n * ny)
    a, b = c.block_a[k], c.block_b[k]
    if anchor != ANCHOR_A:             # (the anchor's own point is left exactly as it is)
        c.point_a[k, 0], c.point_a[k, 1] = unrotate(s.rot, a, px - s.pos[a, 0],
                                                    py - s.pos[a, 1])
    if anchor != ANCHOR_B:
        c.point_b[k, 0], c.point_b[k, 1] = unrotate(s.rot, b, px + u_n * nx - s.pos[b, 0],
                                                    py + u_n * ny - s.pos[b, 1])
    c.us[k] = 0.0


@njit(cache=True)        # not inlined: rare, kept out of the hot loop's code
def log_crack(cracks, time, xa, ya, event, a, b, m):
    """Append a failure to the CrackLog (rows [time, x, y, mode, block_a, block_b, material])."""
    i = cracks.count[0]
    if i < cracks.rows.shape[0]:
        r = cracks.rows
        r[i, 0] = time
        r[i, 1] = xa
        r[i, 2] = ya
        r[i, 3] = event
        r[i, 4] = a
        r[i, 5] = b
        r[i, 6] = m
    cracks.count[0] = i + 1


# parallel=True without a prange: numba's parallel pipeline compiles this loop to code that
# ran 11x faster (13 vs 146 ns per contact on the 2-core VM, 2026-11-21; same results to the
# bit) than the plain pipeline; it still runs on the calling thread. Numba warns that it found
# nothing to parallelise: expected here, so that one warning is silenced.
warnings.filterwarnings("ignore", category=NumbaPerformanceWarning,
                        message=r"(?s).*parallel=True.*no transformation for parallel")
@njit(cache=True, parallel=True)
def add_contact_forces(c, strength, s, cracks, time):
    """All live contacts (``contact_update``), forces added to both blocks in contact order;
    a new failure is appended to ``cracks``."""
    f, pos = s.force, s.pos
    for k in range(c.count[0]):
        fx, fy, xa, ya, event = contact_update(k, c, strength, s)
        a = c.block_a[k]
        b = c.block_b[k]
        if event == 1 or event == 2:
            log_crack(cracks, time, xa, ya, event, a, b, c.material[k])
        f[b, 0] += fx
        f[b, 1] += fy
        f[b, 2] += (xa - pos[b, 0]) * fy - (ya - pos[b, 1]) * fx
        f[a, 0] -= fx
        f[a, 1] -= fy
        f[a, 2] -= (xa - pos[a, 0]) * fy - (ya - pos[a, 1]) * fx
