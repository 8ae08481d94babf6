"""Deformable blocks (UDEC's): constant-strain triangle zones in a floating block frame.

Holds: ``zones`` (the zones' mesh arrays, explicit step, energies, stiffness), ``zone_mesh``
(gmsh meshes of the blocks), ``zone_plasticity`` (Mohr-Coulomb zones with a tension cut-off),
``component`` (the ``Deformable`` bundle, its force component ``add_deformable`` and the
gridpoints' move ``advance_zones``, which the step's integration calls), ``held``
(deformable blocks at the model's boundary, monitoring), ``setup`` (the ``Model`` options
``deformable`` and ``zone_strength`` checked and turned into the bundle).

May import: numpy, numba, gmsh (only when meshing), ``dem_core.step`` (kinematics, nodes),
``dem_core.contact`` (boundary points). Never the driver, the workflow or the output.
"""
