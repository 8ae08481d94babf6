"""Continuum (finite element) reference for the rock-slope toolkit: DOLFINx 0.5.2 + gmsh.

Importing the package is cheap and needs no DOLFINx: `hoek_brown`, `materials`,
`return_mapping`, `newton` and `limit_equilibrium` (Bishop's method) are plain numpy/scipy.
The DOLFINx parts (`mesh`, `model`, `ssr`, `plot`) import DOLFINx when they are imported.

Ten-line example (a Mohr-Coulomb slope raised to failure in a centrifuge)::

    from continuum_ref.mesh import PolygonRegion, build_mesh
    from continuum_ref.materials import MohrCoulomb
    from continuum_ref.model import ContinuumModel
    from continuum_ref.ssr import critical_g
    md = build_mesh([PolygonRegion("rock", [(0, 0), (4, 0), (4, 1), (2, 1), (2, 2), (0, 2)])],
                    h=0.2, points={"crest": (2, 2)})
    model = ContinuumModel(md, MohrCoulomb(E=1e7, nu=0.3, cohesion=1e4, friction=0.0), 1019.4)
    model.fix(lambda x: x[1] < 1e-9)                    # base fixed
    model.fix(lambda x: (x[0] < 1e-9) | (x[0] > 4 - 1e-9), components=(0,))   # rollers
    model.solve_gravity(1.0)
    print(critical_g(model, g_max=6.0).value)           # about 3.9 (exact 3.78)

See docs/continuum.md.
"""
