"""Units and constants shared by both methods: SI inside, degrees at the API.

``STANDARD_GRAVITY`` is the g of a g-level (a centrifuge at n g pulls n x 9.81 m/s^2) in both
the DEM and the continuum; ``MPA`` and ``KPA`` are for reading numbers written in the units
rock engineers quote. Friction and dilation angles are degrees wherever a user writes them
and radians or tangents inside (``contact.materials``, ``continuum_ref.materials``).
"""
from __future__ import annotations

STANDARD_GRAVITY = 9.81     # m/s^2 (the value the thesis's g-levels use)
MPA = 1.0e6                 # Pa
KPA = 1.0e3                 # Pa
