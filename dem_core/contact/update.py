"""The contact search as the driver runs it: surviving contacts kept with their history, new
ones found (``detection.update_contacts``: broad phase on a cell grid, narrow phase vertex
against face), made stiff (``stiffness``) and started stress-free, then sorted for locality; then, with the
option ``divide_interfaces``, every interface whose contacts changed or slid is divided among
them anew (``division``).

A new contact starts stress-free at touching: its elastic normal stress is -kn times its
opening when found, so a contact found open carries nothing until it closes (with deformable
blocks the opening is taken at the deformed points).
"""
from __future__ import annotations

import numpy as np

from . import detection
from .division import divide_interfaces
from .stiffness import set_contact_stiffness

__all__ = ["search_contacts"]


def search_contacts(world, table, new_id, margin, moduli, divide=False):
    """(contacts, changed): ``world``'s contacts after a search within ``margin`` (m) with
    the new ones of material ``new_id`` (-1: none may be made); ``table`` the material table,
    ``moduli`` (E, nu) per block for their stiffness (``stiffness.set_contact_stiffness``).
    ``divide``: divide the interfaces among their contacts (``division``). ``changed``:
    whether the set of contacts or a length changed (the time step must follow). Records
    the search pose in ``world.state``."""
    s = world.state
    old_n = world.contacts.n
    c, n_new = detection.update_contacts(world.contacts, s, world.props, table, new_id, margin,
                                         world.corners, cut=divide)
    if n_new:
        rows = np.arange(c.n - n_new, c.n)
        set_contact_stiffness(c, s, world.corners, table, moduli, rows)
        c.un[rows], c.us[rows] = detection.displacements(c, s, rows, world.corners, world.zones)
        c.sn_elastic[rows] = -c.kn[rows] * c.un[rows]
        c = detection.sort_for_locality(c)
    divided = divide and divide_interfaces(c, s, world.props, table.bonded(), world.corners,
                                           margin)
    s.pos_search[:] = s.pos
    s.theta_search[:] = s.theta
    return c, bool(n_new or c.n != old_n or divided)
