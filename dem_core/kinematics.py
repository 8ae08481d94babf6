"""Rigid-body kinematics of the blocks: small inlined functions used by every kernel.

A block's pose is its centroid ``pos[b]`` and rotation ``theta[b]`` (counter-clockwise, rad),
kept with ``rot[b] = (cos theta, sin theta)``. A body point with local coordinates ``r``
(relative to the centroid, in the block's frame at theta = 0) is at ``x = pos + R r`` and moves
with ``v = vel + omega k x (x - pos)``; a direction ``d`` fixed in the block (a face normal) is
``R d`` in the world::

    R = [[cos, -sin],
         [sin,  cos]]
"""
from __future__ import annotations

import math

from numba import njit

__all__ = ["body_point", "rotate", "unrotate", "point_velocity", "update_rotation",
           "common_normal"]


@njit(cache=True, inline="always")
def rotate(rot, b, dx, dy):
    """R(theta_b) (dx, dy): a vector fixed in block b, in world axes."""
    cos_b, sin_b = rot[b, 0], rot[b, 1]
    return cos_b * dx - sin_b * dy, sin_b * dx + cos_b * dy


@njit(cache=True, inline="always")
def unrotate(rot, b, dx, dy):
    """R(theta_b)^T (dx, dy): a world vector in block b's axes."""
    cos_b, sin_b = rot[b, 0], rot[b, 1]
    return cos_b * dx + sin_b * dy, -sin_b * dx + cos_b * dy


@njit(cache=True, inline="always")
def body_point(pos, rot, b, rx, ry):
    """World position (m) of block b's body point with local coordinates (rx, ry)."""
    x, y = rotate(rot, b, rx, ry)
    return pos[b, 0] + x, pos[b, 1] + y


@njit(cache=True, inline="always")
def point_velocity(pos, vel, omega, b, x, y):
    """Velocity (m/s) of block b's material point now at world (x, y)."""
    return vel[b, 0] - omega[b] * (y - pos[b, 1]), vel[b, 1] + omega[b] * (x - pos[b, 0])


@njit(cache=True, inline="always")
def common_normal(rot, a, b, na_x, na_y, nb_x, nb_y):
    """Unit contact normal from A into B, the same whichever block is called A.

    ``(nb_x, nb_y)``: the A -> B direction fixed in B (minus the outward normal of B's face);
    ``(na_x, na_y)``: the same direction fixed in A (A's face's outward normal) for a contact
    between two faces, (0, 0) for a vertex of A against a face of B. Two faces in contact share
    the bisector of their normals (both blocks agree on it, as 3DEC's common plane); a vertex
    against a face takes the face's normal.
    """
    nx, ny = rotate(rot, b, nb_x, nb_y)
    if na_x == 0.0 and na_y == 0.0:
        return nx, ny
    mx, my = rotate(rot, a, na_x, na_y)
    nx += mx
    ny += my
    ln = math.hypot(nx, ny)
    return nx / ln, ny / ln


@njit(cache=True)
def update_rotation(theta, rot):
    """rot[i] = (cos theta_i, sin theta_i) for every block."""
    for i in range(theta.shape[0]):
        rot[i, 0] = math.cos(theta[i])
        rot[i, 1] = math.sin(theta[i])
