"""Contact forces: each contact's geometry (``contacts.py``), its law (``law.py``) and the
force it adds to its two blocks. Forces go into ``BlockState.force`` ((nb, 3): fx, fy in N/m,
moment in N m/m, CCW +).

The two contacts of a shared edge (``Contacts.partner``) are one linear interface element: each
keeps the stress at its end of the edge (sigma_1, sigma_2: what the law updates and the
strength is checked against, the peak of a linear distribution), and the edge transmits the
resultant of the linear stress between them, i.e. end forces (L/6) (2 sigma_1 + sigma_2) and
(L/6) (sigma_1 + 2 sigma_2) for an edge of length L (the consistent forces of a linear
element; the same for the shear stress). Each contact adds its lumped force (L/2) sigma_i, and
the later of the two adds the difference, (L/6) (sigma_2 - sigma_1) at end 1 and its opposite
at end 2: a couple (``edge_correction``). When one end is open (separated: it carries nothing,
its spring stretched past the cut-off), the edge carries the compressed part of the same linear
field, a triangle whose resultant moves from L/3 towards the closed corner as the edge opens
(a rigid block tips about its corner as on an elastic foundation), the shear stress of the
closed end spread in proportion (so the edge meets Coulomb's limit on its compressed length
x0, tan(phi) times the triangle's resultant). Where x0 grows, the part of the edge that
closes comes in unstressed in shear: the closed end's shear stress is scaled by x0_old / x0
(``Contacts.edge_x0``), so the edge's shear force does not grow with the contact (without it,
t x0 / 2 at a constant t was a spring whose stiffness the rocking varies: an undamped block
rocking on a plane gained energy until it toppled, docs/history.md); where x0 shrinks, the
shear on the part that opens is let go. Once the two contacts have slid apart (their points
no longer span the edge's length to 1 %) they are two point contacts again. ``Model(edge_elements=True)``
turns this on (pairs in ``Contacts.partner``); off, every contact is its own spring. The edge
then turns under a moment M with the rotational stiffness kn L^3/12 and fails (an end reaches
T) at M = T L^2/6, the elastic values; lumped end forces alone give kn L^3/4 and T L^2/2
(three times too stiff and too strong in bending).

Source: the edge is the linear (two-node per side, zero-thickness) joint element of R. E.
Goodman, R. L. Taylor and T. L. Brekke (1968), "A model for the mechanics of jointed rock",
Journal of the Soil Mechanics and Foundations Division, ASCE 94 (SM3), 637-659: normal and
shear springs per unit length between the two faces, the relative displacement interpolated
linearly along the edge, and consistent (not lumped) end forces.
"""
from __future__ import annotations

import warnings

import numpy as np
from numba import njit, types
from numba.extending import overload
from numba.core.errors import NumbaPerformanceWarning

from .boundary_points import deformed_points, rest_points
from .contacts import ANCHOR_A, ANCHOR_B
from ..step.kinematics import body_point, contact_normal, unrotate
from .law import coulomb_law
from .rounding import corner_centre, is_rounded, rounded_contact
from ..step.state import no_parallel

__all__ = ["add_contact_forces", "chunk_forces", "contact_update", "log_crack",
           "edge_correction"]


def contact_points(k, c, s, zones, xb, yb):
    """(xa, ya, xb, yb): contact k's points, A's the body point of its vertex and B's the
    given (xb, yb), or, on deformable blocks, both moved by the zones' displacement
    (``boundary_points.deformed_points``). ``zones`` None: rigid blocks (typed below: the
    deformable branch is then not compiled at all)."""
    raise NotImplementedError("numba-only: called from compiled code")


@overload(contact_points, inline="always")
def _contact_points(k, c, s, zones, xb, yb):
    if isinstance(zones, types.NoneType):
        def rigid(k, c, s, zones, xb, yb):
            xa, ya = body_point(s.pos, s.rot, c.block_a[k], c.point_a[k, 0], c.point_a[k, 1])
            return xa, ya, xb, yb
        return rigid

    def any_blocks(k, c, s, zones, xb, yb):
        if zones.point_offsets.shape[0] == 0:
            xa, ya = body_point(s.pos, s.rot, c.block_a[k], c.point_a[k, 0], c.point_a[k, 1])
            return xa, ya, xb, yb
        return deformed_points(k, c, s, zones)     # points moved by the zones' displacement
    return any_blocks


def body_points_only(zones):
    """True where every contact point is a body point (no zones, or none that move points)."""
    raise NotImplementedError("numba-only: called from compiled code")


@overload(body_points_only, inline="always")
def _body_points_only(zones):
    if isinstance(zones, types.NoneType):
        return lambda zones: True
    return lambda zones: zones.point_offsets.shape[0] == 0


def reanchor_on_zones(k, c, s, zones, nx, ny):
    """After a contact k on a deformable block failed or slipped: its moved point(s) back to
    rest places (``boundary_points.rest_points``), and its gap and offset measured anew from
    them (a rest place is found at the displacement of the stretch it came from, not exactly
    the one it goes to: the next increments are measured from the points as they are, else
    each move adds a spurious increment and slipping or open contacts pump energy into the
    zones). ``zones`` None or empty: nothing."""
    raise NotImplementedError("numba-only: called from compiled code")


@overload(reanchor_on_zones, inline="always")
def _reanchor_on_zones(k, c, s, zones, nx, ny):
    if isinstance(zones, types.NoneType):
        def rigid(k, c, s, zones, nx, ny):
            return None
        return rigid

    def any_blocks(k, c, s, zones, nx, ny):
        a, b = c.block_a[k], c.block_b[k]
        off = zones.point_offsets
        if off.shape[0] != 0 and (off[a + 1] > off[a] or off[b + 1] > off[b]):
            rest_points(k, c, s, zones)
            xa2, ya2, xb2, yb2 = deformed_points(k, c, s, zones)
            c.un[k] = (xb2 - xa2) * nx + (yb2 - ya2) * ny
            c.us[k] = (yb2 - ya2) * nx - (xb2 - xa2) * ny
        return None
    return any_blocks


@njit(cache=True, inline="always")
def contact_update(k, c, strength, s, rnd, zones):
    """Contact k of ``c`` (Contacts) at the blocks' pose ``s`` (BlockState): updates its
    displacements and stresses and returns (fx, fy, xa, ya, event): the force on B (N/m; minus
    it on A), the point it acts at (m: A's vertex, or midway between the two faces' points of
    a face contact; with rounded corners ``rnd``, the point of A's arc) and the law's event
    (1 tension failure, 2 shear failure, 3 slip, 4 open, 5 softening; ``law.coulomb_law``,
    whose damage and plastic work it keeps in the contact). ``zones``: the deformable blocks'
    zones (``deformable.component``; empty: every block rigid, the points are body points),
    whose displacement moves the points. Shared by the serial kernel below and the threaded
    one (``parallel.py``), so both compute the same numbers."""
    a = c.block_a[k]
    b = c.block_b[k]
    xb, yb = body_point(s.pos, s.rot, b, c.point_b[k, 0], c.point_b[k, 1])
    rounded = is_rounded(rnd, c, k)
    if rounded:                            # xa: A's corner centre (rounding.py)
        xf, yf, nx, ny, u_n = rounded_contact(rnd, s, a, b, c.vertex_a[k], c.edge_b[k])
        xa, ya = corner_centre(rnd, s, a, c.vertex_a[k])
        # B's point sits this far across the normal
        reach = u_n + rnd.arc[c.vertex_a[k]] + rnd.arc[c.edge_b[k]]
    else:
        xa, ya, xb, yb = contact_points(k, c, s, zones, xb, yb)
        nx, ny = contact_normal(s, a, b, c.face[k], c.normal_b[k, 0], c.normal_b[k, 1])
        u_n = (xb - xa) * nx + (yb - ya) * ny
        reach = u_n
    u_s = (yb - ya) * nx - (xb - xa) * ny
    s_n, t_s, sn_e, slip, event, kappa, w_frac, w_fric = coulomb_law(
        u_n - c.un[k], u_s - c.us[k], c.sn_elastic[k], c.ts[k], c.kn[k], c.ks[k], strength,
        c.material[k], c.broken[k], c.damage[k])
    c.sn[k] = s_n
    c.ts[k] = t_s
    c.sn_elastic[k] = sn_e
    c.un[k] = u_n
    c.us[k] = u_s
    c.slipping[k] = 1 if (event == 2 or event == 3 or (event == 5 and slip != 0.0)) else 0
    if event != 0:                         # (rare: the elastic path writes no more than this)
        c.up[k] += slip
        c.damage[k] = kappa
        lw = _work_length(k, c)
        c.work_fracture[k] += lw * w_frac
        c.work_friction[k] += lw * w_fric
        if event == 1 or event == 2:
            c.broken[k] = event
        _reanchor(k, c, s, xa, ya, xb, yb, reach, nx, ny)
        reanchor_on_zones(k, c, s, zones, nx, ny)
    # the point the force acts at
    anchor = c.anchor[k]
    px = xa if anchor == ANCHOR_A else (xb if anchor == ANCHOR_B else 0.5 * (xa + xb))
    py = ya if anchor == ANCHOR_A else (yb if anchor == ANCHOR_B else 0.5 * (ya + yb))
    if rounded:                            # on A's arc, or at B's corner on A's face
        d = rnd.arc[c.vertex_a[k]]
        px, py = xf + d * nx, yf + d * ny
    L = c.length[k]
    return L * (s_n * nx - t_s * ny), L * (s_n * ny + t_s * nx), px, py, event


@njit(cache=True, inline="always")
def _work_length(k, c):
    """Length (m) over which contact k's stresses do plastic work: its own length, or, where k
    is the closed end of an edge whose other end was open at the last step, x0 / 2 (x0 the
    compressed length, ``Contacts.edge_x0``): the edge transmits k's shear stress t as the
    triangle's resultant t x0 / 2 (module docstring), and a rigid block slips the same along
    the whole edge, so its friction work is t x0 / 2 times the slip, not t L_k times it."""
    p = c.partner[k]
    if p >= 0:
        x0 = c.edge_x0[k]
        if x0 > 0.0 and c.edge_x0[p] == 0.0:
            return 0.5 * x0
    return c.length[k]


@njit(cache=True, inline="always")
def _force_point(k, c, s):
    """World point (m) the force of contact k acts at (its anchor: ``contact_update``)."""
    anchor = c.anchor[k]
    if anchor == ANCHOR_A:
        return body_point(s.pos, s.rot, c.block_a[k], c.point_a[k, 0], c.point_a[k, 1])
    xb, yb = body_point(s.pos, s.rot, c.block_b[k], c.point_b[k, 0], c.point_b[k, 1])
    if anchor == ANCHOR_B:
        return xb, yb
    xa, ya = body_point(s.pos, s.rot, c.block_a[k], c.point_a[k, 0], c.point_a[k, 1])
    return 0.5 * (xa + xb), 0.5 * (ya + yb)


# the two halves of an edge act as one element while their points span the edge's length to
# within 1 % (squared: 2 %); once they have slid apart they are two point contacts
SPAN_TOLERANCE = 0.02


@njit(cache=True, inline="always")
def edge_correction(k, c, s, xk, yk):
    """What turns the lumped forces of contact k and its partner p (this step's stresses:
    p < k in contact order) into the edge's element (module docstring): (fx, fy) the extra
    force on B (N/m; minus it on A), and the extra moments (N m/m) on B about B's centroid and
    on A about A's. The forces act at k's point (xk, yk) and at p's. Keeps the edge's
    compressed length in ``Contacts.edge_x0`` and scales a closed end's shear stress for the
    next step where it grew (module docstring): call once per edge and step."""
    xp, yp = _force_point(c.partner[k], c, s)
    return edge_share(k, c, s, xk, yk, xp, yp)


@njit(cache=True, inline="always")
def edge_share(k, c, s, xk, yk, xp, yp):
    """``edge_correction`` with the partner's force point (xp, yp) given (the contact loop
    has it from the partner's own update, the contact just before)."""
    p = c.partner[k]
    le = c.length[k] + c.length[p]
    span = (xk - xp) * (xk - xp) + (yk - yp) * (yk - yp)
    if abs(span - le * le) > SPAN_TOLERANCE * le * le:
        c.edge_x0[k], c.edge_x0[p] = 0.0, 0.0
        return 0.0, 0.0, 0.0, 0.0        # the halves slid apart: two point contacts again
    sk, sp = c.sn[k], c.sn[p]
    closed_k, closed_p = sk == c.sn_elastic[k], sp == c.sn_elastic[p]
    if closed_k and closed_p:            # linear: a couple, (L/6)(s_p - s_k) at k, minus at p
        w = le / 6.0
        dk, dt = w * (sp - sk), w * (c.ts[p] - c.ts[k])
        dp, dtp = -dk, -dt
        _grown(k, c, le)
        _grown(p, c, le)
    elif closed_k and sk > 0.0:          # p open: the compressed part of the linear field
        rk, rp = _open_end(sk, c.sn_elastic[p], le, c.length[k])
        lk = c.length[k]
        dk, dp, dt, dtp = (rk - 1.0) * lk * sk, rp * lk * sk, (rk - 1.0) * lk * c.ts[k], \
            rp * lk * c.ts[k]
        _half_open(k, p, c, 2.0 * (rk + rp) * lk)
    elif closed_p and sp > 0.0:          # k open
        rp, rk = _open_end(sp, c.sn_elastic[k], le, c.length[p])
        lp = c.length[p]
        dp, dk, dtp, dt = (rp - 1.0) * lp * sp, rk * lp * sp, (rp - 1.0) * lp * c.ts[p], \
            rk * lp * c.ts[p]
        _half_open(p, k, c, 2.0 * (rp + rk) * lp)
    else:
        c.edge_x0[k], c.edge_x0[p] = 0.0, 0.0
        return 0.0, 0.0, 0.0, 0.0
    a, b = c.block_a[k], c.block_b[k]
    nx, ny = contact_normal(s, a, b, c.face[k], c.normal_b[k, 0], c.normal_b[k, 1])
    fkx, fky = dk * nx - dt * ny, dk * ny + dt * nx
    fpx, fpy = dp * nx - dtp * ny, dp * ny + dtp * nx
    mb = ((xk - s.pos[b, 0]) * fky - (yk - s.pos[b, 1]) * fkx
          + (xp - s.pos[b, 0]) * fpy - (yp - s.pos[b, 1]) * fpx)
    ma = ((xk - s.pos[a, 0]) * fky - (yk - s.pos[a, 1]) * fkx
          + (xp - s.pos[a, 0]) * fpy - (yp - s.pos[a, 1]) * fpx)
    return fkx + fpx, fky + fpy, mb, ma


@njit(cache=True, inline="always")
def _half_open(q, o, c, x0):
    """Edge with closed end q and open end o, its compressed length now x0 (m). Where it was
    half open at the last step too and x0 shrank from x_old, the shear on the part that opened
    is let go at q's stress t (module docstring): the edge's elastic shear energy, x0 t^2 /
    (6 ks) (``monitor.strain_energy``), falls by (x_old - x0) t^2 / (6 ks) with no work done,
    booked as friction work. Then ``_grown``; o's x0 is 0."""
    x_old = c.edge_x0[q]
    if x0 < x_old and c.edge_x0[o] == 0.0:
        t = c.ts[q]
        c.work_friction[q] += t * t * (x_old - x0) / (6.0 * c.ks[q])
    _grown(q, c, x0)
    c.edge_x0[o] = 0.0


@njit(cache=True, inline="always")
def _grown(q, c, x0):
    """Closed end q of an edge whose compressed length is now x0 (m): if it was x0_old < x0
    at the last step (``Contacts.edge_x0``), q's shear stress is scaled by x0_old / x0 for the
    next step, so the shear force t x0 / 2 does not grow with the contact (the part that
    closes comes in unstressed); the elastic energy that lets go by the open edge's measure
    (``monitor.strain_energy``), x0_old t^2 (1 - x0_old / x0) / (6 ks), is booked as friction
    work. x0 is kept for the next step."""
    x_old = c.edge_x0[q]
    if 0.0 < x_old < x0:
        t = c.ts[q]
        f = x_old / x0
        c.work_friction[q] += t * t * x_old * (1.0 - f) / (6.0 * c.ks[q])
        c.ts[q] = t * f
    if x_old != x0:                # (a closed edge's x0 rarely changes: no store then)
        c.edge_x0[q] = x0


@njit(cache=True, inline="always")
def _open_end(s_closed, e_open, le, l_closed):
    """(closed end's share, open end's share) of the edge's force, each as a fraction of the
    closed end's lumped force l_closed s, when one end of an edge of length ``le`` is open
    (elastic stress ``e_open`` < 0) and the other carries ``s_closed`` > 0: the edge carries
    the compressed part of the linear field, a triangle over x0 = le s / (s - e) with its
    resultant s x0 / 2 at x0 / 3 from the closed end, shared between the ends by statics. The
    closed end's shear stress is spread the same way (slip stays at the friction limit)."""
    x0 = le * s_closed / (s_closed - e_open)
    total = 0.5 * x0 / l_closed
    far = total * x0 / (3.0 * le)
    return total - far, far


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
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


# parallel=True without a prange: the parfor pass first simplifies the typed IR (copy
# propagation), which removes the bundle copies that the inline="always" helpers leave and with
# them the reference counting of every array in the contact loop: 18x faster than the plain
# pipeline, same results to the bit (benchmarks/trials/numba_pipelines.py, docs/performance.md). It
# still runs on the calling thread; numba's warning that it found nothing to parallelise is
# expected here, so that one warning is silenced.
warnings.filterwarnings("ignore", category=NumbaPerformanceWarning,
                        message=r"(?s).*parallel=True.*no transformation for parallel")
# Over 60 lines: the one contact loop of the serial and the threaded kernels (the law
# compiles once); split into calls, each would copy and reference-count the bundles per contact
@njit(cache=True, parallel=True)
def chunk_forces(c, strength, s, rnd, zones, par, edges, j, cracks, time):
    """The contact loop of both kernels; returns the number of bond failures it kept.

    ``j < 0``, the serial kernel: every live contact (``contact_update``), its force added to
    both blocks in contact order (the caller zeroes the forces first), a failure appended to
    ``cracks`` at once. ``j >= 0``, chunk j of the threaded kernel (``parallel.py``, ``par`` its
    Parallel bundle): the chunk's owned blocks zeroed, its contacts' forces added to the owned
    blocks the same way, and kept in ``par.work`` where a block is shared or a bond failed (the
    failures' events in ``par.events``, logged after the region in contact order); an edge's
    share whose partner lies in the chunk is computed here and kept in ``par.edge_work`` where
    a block is shared. One loop for both: the same machine arithmetic, and numba compiles the
    law once."""
    serial = j < 0
    f, pos, owner, work = s.force, s.pos, par.owner, par.work
    if serial:
        k0, k1 = 0, c.count[0]
    else:
        k0, k1 = par.first[j], par.first[j + 1]
        for r in range(par.own_offsets[j], par.own_offsets[j + 1]):
            i = par.own_blocks[r]
            f[i, 0] = 0.0
            f[i, 1] = 0.0
            f[i, 2] = 0.0
    failures = 0
    last, lx, ly = np.int64(-1), 0.0, 0.0      # the last contact whose force point is kept
    # range from 0: numba then knows k >= 0 and drops the negative-index wraparound of every
    # array access (a loop over range(k0, k1) ran 20 % slower than range(n)); the skipped part
    # costs a compare each. (An unsigned index does it too, but compiles every helper again.)
    for k in range(k1):
        if k < k0:
            continue
        fx, fy, xa, ya, event = contact_update(k, c, strength, s, rnd, zones)
        a = c.block_a[k]
        b = c.block_b[k]
        own_a = serial or owner[a] == j
        own_b = serial or owner[b] == j
        if event == 1 or event == 2:
            failures += 1
            if serial:
                log_crack(cracks, time, xa, ya, event, a, b, c.material[k])
            else:
                par.events[k] = event
        if not serial and (not (own_a and own_b) or event == 1 or event == 2):
            work[k, 0] = fx
            work[k, 1] = fy
            work[k, 2] = xa
            work[k, 3] = ya
        if own_b:
            f[b, 0] += fx
            f[b, 1] += fy
            f[b, 2] += (xa - pos[b, 0]) * fy - (ya - pos[b, 1]) * fx
        if own_a:
            f[a, 0] -= fx
            f[a, 1] -= fy
            f[a, 2] -= (xa - pos[a, 0]) * fy - (ya - pos[a, 1]) * fx
        p = c.partner[k] if edges else -1
        if 0 <= p < k and p >= k0:     # the edge's share (``edge_correction``): partner here
            if p == last:              # its point from its own update (the same arithmetic)
                gx, gy, mb, ma = edge_share(k, c, s, xa, ya, lx, ly)
            else:
                gx, gy, mb, ma = edge_correction(k, c, s, xa, ya)
            if not (own_a and own_b):  # for the shared pass (the owned blocks may move)
                ew = par.edge_work
                ew[k, 0] = gx
                ew[k, 1] = gy
                ew[k, 2] = mb
                ew[k, 3] = ma
            if own_b:
                f[b, 0] += gx
                f[b, 1] += gy
                f[b, 2] += mb
            if own_a:
                f[a, 0] -= gx
                f[a, 1] -= gy
                f[a, 2] -= ma
        # a point kept only where _force_point would compute the same: no reanchoring this
        # step, sharp corners, body points (the edge elements' own case)
        if edges and event == 0 and not is_rounded(rnd, c, k) and body_points_only(zones):
            last, lx, ly = np.int64(k), xa, ya
        else:
            last = np.int64(-1)
    return failures


@njit(cache=True)
def add_contact_forces(c, strength, s, cracks, time, rnd, edges, zones):
    """All live contacts (``contact_update``), forces added to both blocks in contact order;
    a new failure is appended to ``cracks``. ``rnd``: the corners' Rounding (``rounding.py``;
    empty: sharp). ``edges``: the edge elements (module docstring). ``zones``: the deformable
    blocks' zones (``deformable.component``; empty: rigid blocks). (``chunk_forces`` with
    ``j = -1`` and an empty Parallel bundle: the threaded kernel's loop, compiled once.)"""
    # np.int64(-1), not -1: a literal argument is a signature of its own (Literal[int](-1)),
    # and the law would be compiled again for the threaded kernel's int64 chunk index
    chunk_forces(c, strength, s, rnd, zones, no_parallel(), edges, np.int64(-1), cracks, time)
