"""Contacts between blocks and what they carry.

Holds: ``contacts`` (the contact arrays), ``law`` (the flaw/joint law), ``forces`` (a
contact's geometry, law and force on its blocks; the edge element), ``detection`` (the search
for new contacts), ``rounding`` (rounded corners), ``boundary_points`` (where a contact acts on
a deformable block), ``materials`` (material tables), ``elastic`` (stiffness in series,
lattice moduli).

May import: numpy, numba, ``dem_core.step.kinematics`` and ``dem_core.step.state`` (the
bundles), ``dem_core.geometry.blocks``. Never the driver, the workflow or the output.
"""
