"""What a run shows: measures, verdicts, files and pictures.

Holds: ``monitor`` (unbalanced ratio, energies, histories, the solve verdict, the instability
diagnosis), ``rupture`` (the rupture surface from the crack log), ``io`` (model files), ``vtk``
(ParaView output), ``plot`` (matplotlib pictures), ``energy`` (the energy account),
``sections`` (forces across a cut: a member's thrust line),
``fingerprint`` (hashes of a final state and of results: same input, same bits).

May import: numpy, matplotlib, meshio (VTK only), ``dem_core.step.state``,
``dem_core.contact``, ``dem_core.components``, ``dem_core.deformable`` (their bundles and
measures). Never the driver or the workflow: the driver passes its bundles in.
"""
