"""The stiffness of a contact when it is made: its material's kn, ks in series with the two
blocks it joins (``elastic.series_stiffness``: a block of modulus E and Poisson ratio nu adds
the compliance of a column of its depth h behind the contact, h / E' in plane strain)."""
from __future__ import annotations

import numpy as np

from .elastic import series_stiffness

__all__ = ["set_contact_stiffness"]


def set_contact_stiffness(contacts, state, corners, table, moduli, rows) -> None:
    """kn, ks (Pa/m) of ``contacts`` rows ``rows``: the material table's ``table.kn``,
    ``table.ks`` in series with the blocks on either side; ``moduli`` = (E, nu) per block
    (E = inf: rigid; a deformable block's zones carry their own elasticity, so pass inf for
    them). Set when a contact is made and when its material's stiffness changes; the
    contact's stresses are kept."""
    rows = np.asarray(rows, dtype=np.int64)
    if rows.size == 0:
        return
    c, st = contacts, state
    block_E, block_nu = moduli
    a, b, m = c.block_a[rows], c.block_b[rows], c.material[rows]
    xa = c.position(st.pos, st.rot)[rows]
    n = c.normal(st, corners)[rows]
    h_a = np.abs(((xa - st.pos[a]) * n).sum(axis=1))
    h_b = np.abs(((xa - st.pos[b]) * n).sum(axis=1))
    c.kn[rows], c.ks[rows] = series_stiffness(table.kn[m], table.ks[m], h_a, h_b,
                                              block_E[a], block_nu[a], block_E[b],
                                              block_nu[b])
