"""Contact materials (flaws, joints) as tables indexed by material id.

A ``Material`` is what a user writes (friction in degrees); a ``MaterialTable`` is what the
kernels read (flat float64 arrays, friction as tan). ``material_table`` maps the
``BlockSystem.material_names`` ("flaw:rock", "joint:bedding", ...) to materials by exact name
or shell-style pattern ("flaw:*"), and checks every value before any compute starts.

Units: kn, ks in Pa/m (stress per unit relative displacement); tensile strength, cohesion in Pa;
friction angles in degrees at the API. ``breakable=False`` makes a contact glued (elastic, no
tension cut-off, no slip): "conventional DEM" is the same scene with flaw materials unbreakable
(``material_table(..., unbreakable="flaw:*")``).
"""
from __future__ import annotations

import fnmatch
import math
from dataclasses import dataclass, replace

import numpy as np

__all__ = ["Material", "MaterialTable", "material_for", "material_table",
           "COL_TENSILE_STRENGTH", "COL_COHESION", "COL_TAN_FRICTION",
           "COL_RESIDUAL_TENSILE_STRENGTH", "COL_RESIDUAL_COHESION",
           "COL_RESIDUAL_TAN_FRICTION", "COL_BREAKABLE", "STRENGTH_COLUMNS"]

# the columns of ``MaterialTable.strength_array()`` (one row per material), what the kernels
# read: peak T, c, tan phi, residual T, c, tan phi, and breakable (1.0; 0.0: glued)
COL_TENSILE_STRENGTH = 0
COL_COHESION = 1
COL_TAN_FRICTION = 2
COL_RESIDUAL_TENSILE_STRENGTH = 3
COL_RESIDUAL_COHESION = 4
COL_RESIDUAL_TAN_FRICTION = 5
COL_BREAKABLE = 6
STRENGTH_COLUMNS = 7


@dataclass(frozen=True)
class Material:
    """One contact material (thesis eqs 3.1-3.5).

    Parameters
    ----------
    kn, ks : float
        Normal and shear stiffness, Pa/m (> 0).
    tensile_strength, cohesion : float
        Peak T and c, Pa (>= 0).
    friction : float
        Peak friction angle, degrees, in [0, 90).
    residual_tensile_strength, residual_cohesion : float
        Values after a tensile or shear failure, Pa (default 0).
    residual_friction : float or None
        Friction after failure, degrees; None keeps the peak friction (the thesis's law).
    breakable : bool
        False makes the contact glued: elastic with no strength limit.
    """

    kn: float
    ks: float
    tensile_strength: float = 0.0
    cohesion: float = 0.0
    friction: float = 30.0
    residual_tensile_strength: float = 0.0
    residual_cohesion: float = 0.0
    residual_friction: float | None = None
    breakable: bool = True

    def validated(self, name: str = "material") -> "Material":
        """Return self after checking every value; raise ValueError naming the bad one."""
        for field_name in ("kn", "ks"):
            v = getattr(self, field_name)
            if not (isinstance(v, (int, float, np.floating, np.integer)) and math.isfinite(v) and v > 0):
                raise ValueError(f"{name}: {field_name} must be a finite stiffness > 0 Pa/m, got {v!r}")
        for field_name in ("tensile_strength", "cohesion", "residual_tensile_strength",
                           "residual_cohesion"):
            v = getattr(self, field_name)
            if not (math.isfinite(v) and v >= 0):
                raise ValueError(f"{name}: {field_name} must be finite and >= 0 Pa, got {v!r}")
        for field_name in ("friction", "residual_friction"):
            v = getattr(self, field_name)
            if v is None:
                continue
            if not (math.isfinite(v) and 0 <= v < 90):
                raise ValueError(f"{name}: {field_name} must be in [0, 90) degrees, got {v!r}")
        return self

    def with_strength(self, **changes) -> "Material":
        """A copy with some fields changed (e.g. ``tensile_strength=0.5e6``), validated."""
        return replace(self, **changes).validated()


@dataclass
class MaterialTable:
    """Materials as flat arrays indexed by material id (what the kernels read).

    Attributes (nm materials)
    ----------
    names : list[str]
    kn, ks : (nm,) float64, Pa/m.
    tensile_strength, cohesion, tan_friction : (nm,) float64, Pa, Pa, -. Peak values.
    residual_tensile_strength, res_cohesion, res_tan_friction : (nm,) float64. Residual
        values.
    breakable : (nm,) int8. 0 = glued.
    """

    names: list
    kn: np.ndarray
    ks: np.ndarray
    tensile_strength: np.ndarray
    cohesion: np.ndarray
    tan_friction: np.ndarray
    residual_tensile_strength: np.ndarray
    res_cohesion: np.ndarray
    res_tan_friction: np.ndarray
    breakable: np.ndarray

    @classmethod
    def from_materials(cls, names, materials) -> "MaterialTable":
        mats = [m.validated(n) for n, m in zip(names, materials)]

        def col(f):
            return np.array([f(m) for m in mats], dtype=np.float64)

        def tan(deg):
            return math.tan(math.radians(deg))

        return cls(
            names=list(names),
            kn=col(lambda m: m.kn), ks=col(lambda m: m.ks),
            tensile_strength=col(lambda m: m.tensile_strength),
            cohesion=col(lambda m: m.cohesion),
            tan_friction=col(lambda m: tan(m.friction)),
            residual_tensile_strength=col(lambda m: m.residual_tensile_strength),
            res_cohesion=col(lambda m: m.residual_cohesion),
            res_tan_friction=col(lambda m: tan(m.friction if m.residual_friction is None
                                               else m.residual_friction)),
            breakable=np.array([1 if m.breakable else 0 for m in mats], dtype=np.int8),
        )

    def bonded(self) -> np.ndarray:
        """(nm,) bool: an intact contact of this material is a bond (can fail, or is glued)."""
        return ((self.tensile_strength > self.residual_tensile_strength)
                | (self.cohesion > self.res_cohesion)
                | (self.breakable == 0))

    def strength_array(self) -> np.ndarray:
        """(nm, 7) float64 rows [T, c, tan phi, T_res, c_res, tan phi_res, breakable] for kernels
        (the columns ``COL_TENSILE_STRENGTH`` ... ``COL_BREAKABLE``)."""
        cols = {COL_TENSILE_STRENGTH: self.tensile_strength, COL_COHESION: self.cohesion,
                COL_TAN_FRICTION: self.tan_friction,
                COL_RESIDUAL_TENSILE_STRENGTH: self.residual_tensile_strength,
                COL_RESIDUAL_COHESION: self.res_cohesion,
                COL_RESIDUAL_TAN_FRICTION: self.res_tan_friction,
                COL_BREAKABLE: self.breakable.astype(np.float64)}
        return np.ascontiguousarray(np.column_stack([cols[k] for k in range(STRENGTH_COLUMNS)]))


def material_for(name: str, mapping: dict) -> Material:
    """The material of contact material ``name``: its exact key, else the longest matching
    fnmatch pattern of ``mapping`` (ValueError naming it when none matches)."""
    if name in mapping:
        return mapping[name]
    hits = [pat for pat in mapping if fnmatch.fnmatchcase(name, pat)]
    if not hits:
        raise ValueError(f"no material given for contact material {name!r}; "
                         f"mapping keys are {sorted(mapping)}")
    # The most specific (longest) pattern wins, so "joint:*" can be overridden by "joint:bed*".
    return mapping[max(hits, key=len)]


def material_table(material_names, mapping: dict, unbreakable: str | None = None) -> MaterialTable:
    """Map BlockSystem material names to a validated ``MaterialTable``.

    Parameters
    ----------
    material_names : list[str]
        ``BlockSystem.material_names``.
    mapping : dict[str, Material]
        Keys are exact names or fnmatch patterns ("flaw:*", "*"); the longest matching key wins.
    unbreakable : str, optional
        A pattern ("flaw:*") whose materials become glued: the thesis's "conventional UDEC"
        counterpart of a damage-model scene, in which intact rock between joints stays continuous.
    """
    if not isinstance(mapping, dict) or not mapping:
        raise ValueError("materials must be a non-empty dict {name or pattern: Material}")
    for key, m in mapping.items():
        if not isinstance(m, Material):
            raise ValueError(f"materials[{key!r}] is {type(m).__name__}, expected Material")
    names = list(material_names)
    mats = [material_for(n, mapping) for n in names]
    if unbreakable is not None:
        mats = [replace(m, breakable=False) if fnmatch.fnmatchcase(n, unbreakable) else m
                for n, m in zip(names, mats)]
    return MaterialTable.from_materials(names, mats)
