"""Rigid-body kinematics of the blocks: small inlined functions used by every kernel.

A block's pose is its centroid ``pos[b]`` and rotation ``theta[b]`` (counter-clockwise, rad),
kept with ``rot[b] = (cos theta, sin theta)`` and ``rot_half[b]`` (the same of theta / 2). A body point with local coordinates ``r``
(relative to the centroid, in the block's frame at theta = 0) is at ``x = pos + R r`` and moves
with ``v = vel + omega k x (x - pos)``; a direction ``d`` fixed in the block (a face normal) is
``R d`` in the world::

    R = [[cos, -sin],
         [sin,  cos]]
"""
from __future__ import annotations

import math

from numba import njit

__all__ = ["body_point", "rotate", "unrotate", "point_velocity", "set_rotation", "update_rotation",
           "contact_normal"]


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
def contact_normal(s, a, b, face, nb_x, nb_y):
    """Unit contact normal from A into B, the same whichever block is called A.

    ``(nb_x, nb_y)``: the A -> B direction fixed in B (minus the outward normal of B's face),
    equal to A's face's outward normal in A's frame for two faces in contact (``face`` = 1:
    both were made with the blocks unrotated). A vertex against a face takes the face's normal,
    R(theta_B) n; two faces take the bisector of their normals, R((theta_A + theta_B) / 2) n
    = R(theta_A / 2) R(theta_B / 2) n (both blocks agree on it, as 3DEC's common plane), from
    the half-angle rotations ``s.rot_half`` (no square root in the contact loop).
    """
    if face == 0:
        return rotate(s.rot, b, nb_x, nb_y)
    x, y = rotate(s.rot_half, b, nb_x, nb_y)
    return rotate(s.rot_half, a, x, y)


@njit(cache=True, inline="always")
def set_rotation(theta, rot, rot_half, i):
    """rot[i] = (cos theta_i, sin theta_i), rot_half[i] the same of theta_i / 2."""
    ch = math.cos(0.5 * theta[i])
    sh = math.sin(0.5 * theta[i])
    rot_half[i, 0] = ch
    rot_half[i, 1] = sh
    rot[i, 0] = ch * ch - sh * sh              # double-angle: two trig calls per block, not four
    rot[i, 1] = 2.0 * sh * ch


@njit(cache=True)
def update_rotation(theta, rot, rot_half):
    """``set_rotation`` of every block."""
    for i in range(theta.shape[0]):
        set_rotation(theta, rot, rot_half, i)
