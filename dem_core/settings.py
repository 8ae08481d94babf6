"""Two records of settings, each validated once: how a model is built and stepped
(``SolverOptions``) and how a solve or a search level is run and judged (``SolveSettings``).

``SolverOptions`` is what ``Model(blocks, materials, density, **options)`` takes besides the
blocks, the materials and the density; a scene's ``"solver"`` keys are its fields
(``SCENE_SOLVER_KEYS``: all but the block moduli, which a scene gives at its top level).
``SolveSettings`` is carried by ``Model.solve``, the ``Solve`` stage, every search stage
(``RaiseGravity``, ``FactorOfSafety``, ``StrengthSchedule``) and the search engine
(``workflow.limit.search_failure``), with one set of defaults.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

__all__ = ["SolverOptions", "SolveSettings", "STEP_ESTIMATES", "JUDGES", "BUDGET_STEPS",
           "SCENE_SOLVER_KEYS", "per_block", "search_margin", "new_contact_material",
           "material_names"]

STEP_ESTIMATES = ("bound", "eigen", "auto")     # how the critical step is found
JUDGES = ("budget", "response")         # how a solve's verdict is found (SolveSettings.judge)
BUDGET_STEPS = 20_000                   # the budget judge's step budget when none is given


def _whole(v) -> bool:
    return isinstance(v, (int, np.integer)) and not isinstance(v, bool)


@dataclass(frozen=True)
class SolverOptions:
    """How a model is built and stepped (``Model``'s options; units SI, angles in degrees).

    block_E, block_nu : block modulus (Pa; float or (nb,) array) and Poisson ratio, a
        compliance in series with every contact spring (``contact.elastic.series_stiffness``).
        None: rigid blocks, all elasticity in the contacts.
    unbreakable : material-name pattern made glued (e.g. "flaw:*": the conventional model).
    damping : local non-viscous damping coefficient alpha in [0, 1) (0.8 quasi-static).
    safety : time step = safety x critical step, in (0, 1].
    step_estimate : how the critical step 2 / omega_max is found: "bound" (Gershgorin, block
        by block, ``step.run.frequency_bound``), "eigen" (the largest eigenvalue of the
        contact stiffness, ``step.critical_step``; rigid blocks with sharp corners only) or
        "auto" ("eigen" where it applies, else "bound"). docs/mechanics.md and
        docs/performance.md give how far the bound is from the step (1.35-2.0 times).
    mass_scaling : blocks stiffer than the median block get more inertial mass (gravity uses
        the real mass), so slivers do not set the step. Quasi-static runs only.
    dt : a fixed time step, s (None: automatic).
    search_margin : contact search distance, m (None: 5 % of the median block radius); the
        search runs again when a block has moved half of it.
    new_contact_material : material of contacts the search finds (None: that of most shared
        edges).
    history_every : steps between history records.
    threads : threads for the step (1: the serial kernels; the threaded ones give the same
        bits, docs/performance.md "Two threads").
    kinetic_damping : every that many steps (0: off) the free velocities are zeroed at a
        kinetic-energy peak (dynamic relaxation, ``step.relaxation``).
    kinetic_adaptive : a kinetic-damping stop that came late (after the peak, between two
        checks) halves the check interval, down to 1 step, until the next solve, and the
        checks' spacing is spread over 1/2 to 1 interval (``step.relaxation``); False: a check
        every ``kinetic_damping`` steps (the rule before 2026-11-30).
    edge_elements : the two contacts of a shared edge act as one linear interface element
        (``contact.forces.edge_correction``): the exact bending of a bonded edge, the contact
        model whose answers converge with block size (docs/mechanics.md, "One edge, one
        linear element").
        None (the default): edge elements where every block is rigid, the end-spring pair
        where the scene has deformable blocks (edge elements are not built on zones yet);
        False: the end-spring pair everywhere (the default before 2026-12-01, three times
        too stiff and too strong in bending).
    rounding : rounded corners (``contact.rounding``): "auto" (the default since 2026-12-02;
        each block's corners rounded with 1 % of the model's median edge, less on a sliver;
        sharp corners on deformable blocks, which do not take rounding yet), a radius d in m
        for every corner, or 0: sharp corners (the default before; docs/mechanics.md,
        "Corners that do not snag", gives the numbers it moved).
    divide_interfaces : at each contact search, divide every interface whose contacts have
        changed or slid among them from the current geometry (``contact.division``), and cut
        a new contact's length to the face it touches (the default since 2026-12-02); False:
        lengths as made and never divided, the default before (docs/mechanics.md, "Contact
        lengths after sliding", gives the numbers it moved).
    deformable : {block group or "*": zone size m} (None: rigid blocks; ``deformable``).
    zone_strength : {block group or "*": dict(cohesion=Pa, friction=deg, dilation=deg,
        tensile_strength=Pa)} Mohr-Coulomb zones (needs ``deformable``).
    """

    block_E: object = None
    block_nu: object = 0.25
    unbreakable: str | None = None
    damping: float = 0.8
    safety: float = 0.5
    step_estimate: str = "bound"
    mass_scaling: bool = False
    dt: float | None = None
    search_margin: float | None = None
    new_contact_material: str | None = None
    history_every: int = 100
    threads: int = 1
    kinetic_damping: int = 0
    kinetic_adaptive: bool = True
    edge_elements: bool | None = None
    rounding: float | str = "auto"
    divide_interfaces: bool = True
    deformable: dict | None = None
    zone_strength: dict | None = None

    # options a built model keeps (``Model.set_options`` refuses them)
    FIXED_AT_BUILD = frozenset({"block_E", "block_nu", "deformable", "zone_strength", "rounding",
                                "edge_elements", "unbreakable"})

    def validated(self) -> "SolverOptions":
        """Itself, after checking every option that needs no blocks (ValueError naming the
        option and its value); the per-group options are checked by ``deformable.setup``."""
        import numba

        if not (isinstance(self.damping, (int, float)) and 0.0 <= self.damping < 1.0):
            raise ValueError(f"damping must be in [0, 1), got {self.damping!r}")
        if not (isinstance(self.safety, (int, float)) and 0.0 < self.safety <= 1.0):
            raise ValueError(f"safety must be in (0, 1], got {self.safety!r}")
        if self.step_estimate not in STEP_ESTIMATES:
            raise ValueError(f"step_estimate must be one of {STEP_ESTIMATES}, got "
                             f"{self.step_estimate!r}")
        if isinstance(self.rounding, str) and self.rounding != "auto":
            raise ValueError(f"rounding must be 'auto' or a length in m (>= 0), got "
                             f"{self.rounding!r}")
        if self.rounding == "auto" and self.deformable is not None:
            # deformable blocks take no rounding yet (``deformable.setup``)
            return dataclasses.replace(self, rounding=0.0).validated()
        if self.step_estimate == "eigen" and self.deformable is not None:
            raise ValueError("step_estimate='eigen' is for rigid blocks; got "
                             f"deformable={self.deformable!r} (use 'bound')")
        if self.edge_elements is None:      # the default: edge elements on rigid blocks
            return dataclasses.replace(self, edge_elements=self.deformable is None).validated()
        if self.dt is not None and not (math.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"dt must be a finite time step > 0 s, got {self.dt!r}")
        most = numba.config.NUMBA_NUM_THREADS
        if not (_whole(self.threads) and 1 <= self.threads <= most):
            raise ValueError(f"threads must be an integer in 1..{most}, got {self.threads!r}")
        if not (_whole(self.kinetic_damping) and self.kinetic_damping >= 0):
            raise ValueError(f"kinetic_damping must be a step interval >= 0 (0: off), got "
                             f"{self.kinetic_damping!r}")
        if not isinstance(self.kinetic_adaptive, bool):
            raise ValueError(f"kinetic_adaptive must be true or false, got "
                             f"{self.kinetic_adaptive!r}")
        if not isinstance(self.divide_interfaces, bool):
            raise ValueError(f"divide_interfaces must be true or false, got "
                             f"{self.divide_interfaces!r}")
        if self.search_margin is not None and not self.search_margin > 0:
            raise ValueError(f"search_margin must be > 0 m, got {self.search_margin!r}")
        return self

    def replace(self, **changes) -> "SolverOptions":
        """A copy with ``changes`` (ValueError naming an unknown option), validated."""
        unknown = set(changes) - {f.name for f in dataclasses.fields(self)}
        if unknown:
            raise ValueError(f"unknown solver option(s) {sorted(unknown)}; options are "
                             f"{sorted(f.name for f in dataclasses.fields(self))}")
        return dataclasses.replace(self, **changes).validated()


# a scene's "solver" keys: every option but the block moduli (the scene's own keys)
SCENE_SOLVER_KEYS = frozenset(f.name for f in dataclasses.fields(SolverOptions)) - {
    "block_E", "block_nu"}


@dataclass(frozen=True)
class SolveSettings:
    """How one solve, or one level of a search, is run and judged.

    ratio : the unbalanced-force ratio that counts as equilibrium (``output.monitor``).
    max_steps : the step budget of the solve (of each level, in a search) for
        ``judge="budget"`` (None: ``BUDGET_STEPS``, 20,000); giving one with no ``judge``
        chooses the budget judge. Not used by ``judge="response"``.
    failure_displacement : m; a block (or watched point) moving more than this during the
        solve has failed (None: no such test).
    creep : m; displacement increments below this do not count as movement: in the budget
        judge's end test (``output.monitor.verdict``; None: 1e-3 of the median block radius,
        or 0 for watched points), and per window of N_r in the response judge's
        (``workflow.response``; None: 1e-3 of the median block radius, at least 1e-6 of it).
    watch : history-point names judged instead of every block (empty: every block).
    settle : stop early as "settled" once the motion has died out (``monitor.settled``).
    judge : "response": "equilibrium", "failing" or "undecided", judged over windows of the
        model's measured response time N_r, with no step budget in the answer
        (``workflow.response``); "budget": the verdict at ``max_steps`` ("equilibrium",
        "settled", "moving" or "failed", ``output.monitor``; the default before 2026-11-30).
        None (the default): "response", or "budget" where ``max_steps`` is given, so a call
        or scene that names a step budget keeps the verdict it had (``validated`` resolves it).
    response_steps : N_r in steps for ``judge="response"`` (None: the model's, measured at
        its first judged solve, ``workflow.response.measure_response``).
    windows : the cap of a ``judge="response"`` solve, in windows (the first three N_r
        steps long; one after a window that slowed is twice as long, up to 8 N_r,
        ``workflow.response.next_span``; 40 windows are at most 289 N_r): a solve that has
        neither come to rest nor shown a mechanism by then is "undecided" (20 before
        2026-12-01: a slow mechanism first seen after about 80 N_r could not be seen again).
    """

    ratio: float = 1e-5
    max_steps: int | None = None
    failure_displacement: float | None = None
    creep: float | None = None
    watch: tuple = ()
    settle: bool = False
    judge: str | None = None
    response_steps: int | None = None
    windows: int = 40

    def validated(self, where="solve") -> "SolveSettings":
        """Itself with ``judge`` and ``max_steps`` resolved (a judge of None is "budget" where
        ``max_steps`` is given, else "response"; the budget judge's ``max_steps`` of None is
        ``BUDGET_STEPS``), after checking each setting (ValueError naming ``where`` and the
        value)."""
        if self.judge is None:
            return dataclasses.replace(
                self, judge="response" if self.max_steps is None else "budget"
            ).validated(where)
        if self.max_steps is None and self.judge == "budget":
            return dataclasses.replace(self, max_steps=BUDGET_STEPS).validated(where)
        if not (isinstance(self.ratio, (int, float)) and not isinstance(self.ratio, bool)
                and self.ratio > 0):
            raise ValueError(f"{where}: ratio must be > 0, got {self.ratio!r}")
        if self.max_steps is not None and not (_whole(self.max_steps) and self.max_steps > 0):
            raise ValueError(f"{where}: max_steps must be a whole number > 0, got "
                             f"{self.max_steps!r}")
        fd = self.failure_displacement
        if fd is not None and not (isinstance(fd, (int, float)) and fd > 0):
            raise ValueError(f"{where}: failure_displacement must be > 0 m, got {fd!r}")
        if self.creep is not None and not (isinstance(self.creep, (int, float))
                                           and self.creep >= 0):
            raise ValueError(f"{where}: creep must be >= 0 m, got {self.creep!r}")
        if not isinstance(self.settle, bool):
            raise ValueError(f"{where}: settle must be true or false, got {self.settle!r}")
        if self.judge not in JUDGES:
            raise ValueError(f"{where}: judge must be one of {JUDGES}, got {self.judge!r}")
        n_r = self.response_steps
        if n_r is not None and not (_whole(n_r) and n_r > 0):
            raise ValueError(f"{where}: response_steps must be a whole number > 0, got {n_r!r}")
        if not (_whole(self.windows) and self.windows >= 2):
            raise ValueError(f"{where}: windows must be a whole number >= 2, got "
                             f"{self.windows!r}")
        return self

    def replace(self, **changes) -> "SolveSettings":
        """A copy with ``changes`` (ValueError naming an unknown setting)."""
        unknown = set(changes) - SOLVE_KEYS
        if unknown:
            raise ValueError(f"unknown solve setting(s) {sorted(unknown)}; settings are "
                             f"{sorted(SOLVE_KEYS)}")
        if "watch" in changes:
            changes["watch"] = tuple(changes["watch"] or ())
        return dataclasses.replace(self, **changes)

    @classmethod
    def of(cls, record) -> "SolveSettings":
        """The settings a stage record carries in its own fields of these names."""
        return cls(**{k: getattr(record, k) for k in SOLVE_KEYS if hasattr(record, k)}
                   ).replace(watch=getattr(record, "watch", ()))


SOLVE_KEYS = frozenset(f.name for f in dataclasses.fields(SolveSettings))
DEFAULT_SOLVE = SolveSettings()


# ---------------------------------------------------------------- resolved against the blocks

def per_block(value, default, name, nb, lower=None, upper=None):
    """(nb,) float64 of a scalar or per-block ``value`` (None: ``default``); ValueError
    naming the first block out of (lower, upper) or not finite."""
    arr = np.full(nb, default, dtype=np.float64) if value is None else \
        np.broadcast_to(np.asarray(value, dtype=np.float64), (nb,)).copy()
    bad = ~np.isfinite(arr) & ~np.isinf(arr) if value is None else ~np.isfinite(arr)
    if lower is not None:
        bad |= arr <= lower
    if upper is not None:
        bad |= arr >= upper
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{name} of block {i} is {arr[i]!r}: out of range ({lower}, {upper})")
    return arr


def search_margin(opts, props) -> float:
    """The option, or 5 % of the median block radius."""
    med_r = float(np.median(props.radius)) if props.radius.size else 1.0
    return 0.05 * med_r if opts.search_margin is None else float(opts.search_margin)


def new_contact_material(opts, blocks):
    """The option, or the material of most shared edges (None: no materials)."""
    names = list(blocks.material_names)
    if opts.new_contact_material is not None or not names:
        return opts.new_contact_material
    return names[int(np.argmax(np.bincount(blocks.edge_material, minlength=len(names))))]


def material_names(blocks, opts) -> list:
    """The table's names: the blocks' materials, and the new-contact material if not one."""
    names = list(blocks.material_names)
    if opts.new_contact_material is not None and opts.new_contact_material not in names:
        names.append(opts.new_contact_material)
    return names
