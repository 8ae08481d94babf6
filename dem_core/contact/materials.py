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

from .softening import SHAPES, critical_displacement, snap_back

__all__ = ["Material", "MaterialTable", "material_for", "material_table",
           "COL_TENSILE_STRENGTH", "COL_COHESION", "COL_TAN_FRICTION",
           "COL_RESIDUAL_TENSILE_STRENGTH", "COL_RESIDUAL_COHESION",
           "COL_RESIDUAL_TAN_FRICTION", "COL_BREAKABLE", "COL_SOFTENING",
           "COL_CRITICAL_OPENING", "COL_CRITICAL_SLIP", "STRENGTH_COLUMNS"]

# the columns of ``MaterialTable.strength_array()`` (one row per material), what the kernels
# read: peak T, c, tan phi, residual T, c, tan phi, breakable (1.0; 0.0: glued), and for a
# softening bond its shape (``softening.SHAPES``; 0: brittle), w_c and s_c (m)
COL_TENSILE_STRENGTH = 0
COL_COHESION = 1
COL_TAN_FRICTION = 2
COL_RESIDUAL_TENSILE_STRENGTH = 3
COL_RESIDUAL_COHESION = 4
COL_RESIDUAL_TAN_FRICTION = 5
COL_BREAKABLE = 6
COL_SOFTENING = 7
COL_CRITICAL_OPENING = 8
COL_CRITICAL_SLIP = 9
STRENGTH_COLUMNS = 10


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
    fracture_energy_I, fracture_energy_II : float
        G_I, G_II, J/m^2 (>= 0; default 0: brittle, the thesis's law). Either above 0 makes a
        bond soften after its peak (``softening.py``): tension and cohesion fall to their
        residuals over the critical opening w_c = G_I / ((T - T_res) A_f) and slip
        s_c = G_II / ((c - c_res) A_f).
    softening : str
        The softening shape, "linear" (A_f = 1/2) or "hordijk" (A_f = 0.1947).
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
    fracture_energy_I: float = 0.0
    fracture_energy_II: float = 0.0
    softening: str = "linear"

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
        for field_name in ("fracture_energy_I", "fracture_energy_II"):
            v = getattr(self, field_name)
            if not (isinstance(v, (int, float, np.floating, np.integer)) and math.isfinite(v)
                    and v >= 0):
                raise ValueError(f"{name}: {field_name} must be finite and >= 0 J/m^2, got {v!r}")
        if self.softening not in SHAPES:
            raise ValueError(f"{name}: softening must be one of {sorted(SHAPES)}, got "
                             f"{self.softening!r}")
        for field_name in ("friction", "residual_friction"):
            v = getattr(self, field_name)
            if v is None:
                continue
            if not (math.isfinite(v) and 0 <= v < 90):
                raise ValueError(f"{name}: {field_name} must be in [0, 90) degrees, got {v!r}")
        check_snap_back(name, self.kn, self.ks, self)
        return self

    @property
    def softens(self) -> bool:
        """A bond with a fracture energy: it softens after its peak (``softening.py``)."""
        bond = (self.tensile_strength > self.residual_tensile_strength
                or self.cohesion > self.residual_cohesion)
        return bond and self.breakable and (self.fracture_energy_I > 0
                                            or self.fracture_energy_II > 0)

    def critical_opening(self) -> float:
        """w_c, m (0: brittle in tension)."""
        return critical_displacement(self.fracture_energy_I,
                                     self.tensile_strength - self.residual_tensile_strength,
                                     self.softening)

    def critical_slip(self) -> float:
        """s_c, m (0: brittle in shear)."""
        return critical_displacement(self.fracture_energy_II,
                                     self.cohesion - self.residual_cohesion, self.softening)

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
    softening : (nm,) float64. The shape code of a softening bond (``softening.SHAPES``), 0
        brittle. critical_opening, critical_slip : (nm,) float64, m. w_c and s_c.
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
    softening: np.ndarray = None
    critical_opening: np.ndarray = None
    critical_slip: np.ndarray = None

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
            softening=col(lambda m: SHAPES[m.softening] if m.softens else 0),
            critical_opening=col(lambda m: m.critical_opening() if m.softens else 0.0),
            critical_slip=col(lambda m: m.critical_slip() if m.softens else 0.0),
        )

    def bonded(self) -> np.ndarray:
        """(nm,) bool: an intact contact of this material is a bond (can fail, or is glued)."""
        return ((self.tensile_strength > self.residual_tensile_strength)
                | (self.cohesion > self.res_cohesion)
                | (self.breakable == 0))

    def strength_array(self) -> np.ndarray:
        """(nm, 10) float64 rows [T, c, tan phi, T_res, c_res, tan phi_res, breakable, softening
        shape, w_c, s_c] for kernels (the columns ``COL_TENSILE_STRENGTH`` ...
        ``COL_CRITICAL_SLIP``)."""
        cols = {COL_TENSILE_STRENGTH: self.tensile_strength, COL_COHESION: self.cohesion,
                COL_TAN_FRICTION: self.tan_friction,
                COL_RESIDUAL_TENSILE_STRENGTH: self.residual_tensile_strength,
                COL_RESIDUAL_COHESION: self.res_cohesion,
                COL_RESIDUAL_TAN_FRICTION: self.res_tan_friction,
                COL_BREAKABLE: self.breakable.astype(np.float64),
                COL_SOFTENING: self.softening, COL_CRITICAL_OPENING: self.critical_opening,
                COL_CRITICAL_SLIP: self.critical_slip}
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


def check_snap_back(name, kn, ks, m: Material) -> None:
    """ValueError naming the material when its softening would snap back at a contact of
    stiffness kn, ks (Pa/m; ``softening.snap_back``). (Friction softening is checked at zero
    normal stress.)"""
    if not m.softens:
        return
    for mode, G, k, L, drop in (
            ("fracture_energy_I", m.fracture_energy_I, kn, m.critical_opening(),
             m.tensile_strength - m.residual_tensile_strength),
            ("fracture_energy_II", m.fracture_energy_II, ks, m.critical_slip(),
             m.cohesion - m.residual_cohesion)):
        snaps = snap_back(G, k, L, drop, m.softening)
        if snaps:
            k_min, need = snaps
            raise ValueError(
                f"{name}: {mode}={G!r} J/m^2 is too small for a contact stiffness of "
                f"{k_min:.4g} Pa/m: the {m.softening} softening would snap back (the peak's "
                f"elastic displacement {drop / k_min:.3g} m against a softening length of "
                f"{L:.3g} m); it needs {mode} > {need:.4g} J/m^2")
