"""Thesis scenes as data: geometry, materials and boundary conditions, one module per case."""

from dem_core.workflow.scene import Boundary

# The centrifuge models' boundaries (thesis fig 4.8, assumed for both cases): the base fixed
# (the blocks touching y = 0), rollers on both sides (the blocks touching x = 0 and x = width
# hold x, free in y and rotation).
CENTRIFUGE_GROUPS = {"base": {"touching": "bottom"}, "left side": {"touching": "left"},
                     "right side": {"touching": "right"},
                     "side walls": {"union": ["left side", "right side"]},
                     "sides": {"minus": ["side walls", "base"]}}
CENTRIFUGE_BOUNDARIES = [Boundary("base"), Boundary("sides", x=True, y=False, rotation=False)]
