"""A water table: hydrostatic pore pressure below a phreatic surface, for both methods.

    p(x, y) = gamma_w max(0, surface(x) - y)          Pa, compression (pushes surfaces apart)

``surface``: a level (m) or a polyline [[x, y], ...] with increasing x (held flat beyond its
ends); ``unit_weight`` gamma_w (N/m^3, 9,810 for fresh water at 1 g). ``on`` says which
contacts of the DEM feel it: "joints" (the joint sets and bedding only: intact rock's flaws are
taken as too tight to let water in) or "all" (flaws too).

DEM (``dem_core.components.water``): the law takes the effective normal stress sn - p for
strength, the pressure pushes the two blocks of a contact apart by p times its length, and a
block face on the model's outer boundary below the surface gets the water force p n on it.
Continuum (``continuum_ref``): the same p as the pore pressure of an effective-stress analysis.
Reference: Hoek & Bray (1981) ch. 6 for the water forces of plane failure; UDEC's ``water``
table (phreatic surface and density) is the same idea.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["WaterTable", "GAMMA_WATER", "check_surface", "surface_height"]

GAMMA_WATER = 9810.0       # N/m^3: 1,000 kg/m^3 x 9.81 m/s^2


def check_surface(surface, where: str, what: str = "surface") -> None:
    """Refuse a surface that is neither a finite level nor a polyline of increasing x, naming
    ``where`` (e.g. "stage 2 (water)")."""
    s = surface
    if isinstance(s, (int, float)):
        if not math.isfinite(s):
            raise ValueError(f"{where}: {what} level {s!r} must be finite")
        return
    p = np.asarray(s, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 2 or not np.all(np.isfinite(p)):
        raise ValueError(f"{where}: {what} must be a level or [[x, y], ...] with at least two "
                         f"finite points, got {s!r}")
    if np.any(np.diff(p[:, 0]) <= 0):
        raise ValueError(f"{where}: the {what} polyline folds back on itself (x must increase "
                         f"along it): {s!r}")


def surface_height(surface, x) -> np.ndarray:
    """Height (m) of a level or polyline ``surface`` above points x (flat beyond its ends)."""
    x = np.asarray(x, dtype=np.float64)
    if isinstance(surface, (int, float)):
        return np.full_like(x, float(surface))
    p = np.asarray(surface, dtype=np.float64)
    return np.interp(x, p[:, 0], p[:, 1])


@dataclass(frozen=True)
class WaterTable:
    """A phreatic surface (module docstring). ``surface`` a level (m), [[x, y], ...], or None
    (no water: as a stage, it drains the model); ``unit_weight`` N/m^3 (> 0); ``on`` "joints"
    or "all". As a stage (kind "water") it puts the table on the model (``Model.set_water``)."""

    surface: float | tuple | None
    unit_weight: float = GAMMA_WATER
    on: str = "joints"

    def check(self, i=None, groups=(), materials=()) -> None:
        where = "water" if i is None else f"stage {i} (water)"
        if self.surface is not None:
            check_surface(self.surface, where, "water table")
        if not (math.isfinite(self.unit_weight) and self.unit_weight > 0):
            raise ValueError(f"{where}: unit_weight {self.unit_weight!r} must be > 0 (N/m^3)")
        if self.on not in ("joints", "all"):
            raise ValueError(f"{where}: on={self.on!r} must be 'joints' or 'all'")

    def pressure(self, x, y) -> np.ndarray:
        """Pore pressure p (Pa, >= 0) at points (x, y)."""
        y = np.asarray(y, dtype=np.float64)
        if self.surface is None:
            return np.zeros_like(y)
        return self.unit_weight * np.maximum(surface_height(self.surface, x) - y, 0.0)

    def run(self, model):
        model.set_water(None if self.surface is None else self)
        n = 0 if model.water_faces is None else len(model.water_faces[0])
        return 0, "set" if self.surface is not None else "drained", {"faces": n}

    def to_dict(self) -> dict:
        s = self.surface
        return {"surface": s if s is None or isinstance(s, (int, float))
                else [list(map(float, q)) for q in s],
                "unit_weight": self.unit_weight, "on": self.on}

    @classmethod
    def from_dict(cls, d) -> "WaterTable":
        s = d.get("surface")
        s = s if s is None or isinstance(s, (int, float)) else tuple(tuple(q) for q in s)
        return cls(s, d.get("unit_weight", GAMMA_WATER), d.get("on", "joints"))
