"""The Model: a block system with materials, loads and a state, and the driver of the solver.

    model = Model(blocks, {"flaw:*": Material(kn=40e9, ks=20e9, tensile_strength=1.1e6,
                                              cohesion=1.2e6, friction=37)}, density=2400)
    model.fix("bottom")
    model.set_gravity(1.0)
    result = model.solve(ratio=1e-5, max_steps=50_000)   # result.verdict == "equilibrium"

Everything the time step reads is a few bundles of flat arrays (``state.py``, ``contacts.py``,
``components/``); this class only resolves names (groups, materials), checks input, builds the
component bundles the scene uses, and calls ``step.run_steps`` (threaded:
``run_steps_threaded``) in chunks of steps (Python runs between chunks, never inside a step).
See docs/architecture.md and docs/mechanics.md.
"""
from __future__ import annotations

import copy
import math

import numpy as np

from .step import critical_step
from .contact import detection
from .output import io
from .output import monitor
from .step import run as stepper
from .geometry.blocks import BlockSystem
from .components import support
from .components import exposed_faces, gravity_bundle, loads_bundle, servo_bundle, water_bundle
from .deformable import component as zone_kernels
from .deformable import held as zone_bc
from .contact.contacts import initial_contacts, split_edges, surface_materials
from .contact.elastic import series_stiffness
from .jit_cache import compiled
from .contact.materials import Material, material_table
from .step.threads import parallel
from .step.threads import region
from .step.threads.parallel import no_parallel, parallel_bundle
from .contact.rounding import rounding_bundle
from .workflow.water import WaterTable
from .deformable.zone_plasticity import strength_table
from .units import STANDARD_GRAVITY
from .step.state import (FIX_ROT, FIX_X, FIX_Y, CrackLog, Integrator, block_props,
                    state_at_rest)

__all__ = ["Model", "ModelUnstable"]

STEP_ESTIMATES = ("bound", "eigen")     # Model(step_estimate=...): how the critical step is found


class ModelUnstable(RuntimeError):
    """The run blew up (NaN or runaway motion); the message names the block and likely cause."""


class Model:
    """A DEM damage-model scene and its state.

    Parameters
    ----------
    blocks : BlockSystem
    materials : dict[str, Material]
        Keyed by ``blocks.material_names`` entries or fnmatch patterns ("flaw:*").
    density : float or (nb,) array, kg/m^3.
    block_E, block_nu : float, optional
        Block modulus (Pa) and Poisson ratio: a compliance in series with every contact spring
        (``elastic.series_stiffness``). None: rigid blocks (all elasticity in the contacts).
    unbreakable : str, optional
        Material-name pattern made glued, e.g. "flaw:*" for the conventional-DEM counterpart.
    damping : float
        Local non-viscous damping coefficient alpha in [0, 1) (0.8 for quasi-static runs).
    safety : float
        Time step = safety x critical step (``step_estimate``).
    step_estimate : str
        How the critical step 2 / omega_max is found. "bound" (default): omega_max^2 bounded
        block by block (``step.frequency_bound``, Gershgorin), safe but high: on the cases'
        blocks its critical step is 1.35-2.9 times below the true one, so at safety 0.5 the
        step is 0.17-0.37 of the critical one (docs/mechanics.md, docs/performance.md).
        "eigen": omega_max^2 the largest eigenvalue of the inertial mass and contact
        stiffness (``critical_step``, a Lanczos solve after each contact search that changes
        the contacts, 5 ms at 1e3 blocks, 77 ms at 1e4): the step is then ``safety`` of the critical
        one. Rigid blocks with sharp corners only (ValueError with ``deformable`` or
        ``rounding``); with support elements their own bound is added.
    mass_scaling : bool
        Make blocks stiffer than the median block heavier (inertial mass only; gravity uses real
        mass) so slivers do not set the time step. For quasi-static runs only.
    dt : float, optional
        A fixed time step, s (otherwise automatic).
    search_margin : float, optional
        Contact search distance, m (default 5 % of the median block radius). The search runs
        again when a block has moved more than half of it.
    new_contact_material : str, optional
        Material name for contacts found by the search (unbonded: residual strengths). Default:
        the material of most shared edges.
    history_every : int
        Steps between history records.
    threads : int
        Threads for the contact forces and the integration (1: the serial kernels; more:
        ``dem_core.step.threads.parallel`` and ``integration.advance_parallel``, bit-for-bit the same results,
        used from ``region.MIN_CONTACTS`` live contacts up when gravity is the only force
        besides the contacts' (the steps of a call in one parallel region), from
        ``parallel.MIN_CONTACTS`` otherwise (a region a step): below that one thread is
        faster). At most numba's thread count (the cores). numba's TBB layer (its default
        when installed) wakes its sleeping worker at every region, 40-90 us on a 2-core VM;
        ``NUMBA_THREADING_LAYER=omp`` spins instead (2-3 us), but GNU OpenMP is not fork-safe:
        not in a process that forks sweep workers afterwards (docs/performance.md).
    kinetic_damping : int
        Dynamic relaxation: every ``kinetic_damping`` steps (0: off) compare the kinetic energy
        with the last check and zero all free velocities when it has fallen (a kinetic-energy
        peak, ``step``). For quasi-static runs of slender structures (toppling columns),
        whose lowest mode local damping turns into a creep lasting many of its periods; 100
        steps suits models whose slowest period is thousands of steps.
    edge_elements : bool
        The two contacts of each shared edge act as one linear interface element
        (``forces.edge_correction``): the exact elastic bending stiffness and strength of a
        bonded edge. Off by default (each contact its own spring at an edge end, three times
        too stiff and strong in bending: the cases' stored numbers are made so). With it the
        Adhikary centrifuge failure g converges with block size (38-40 g from 6 to 3 mm blocks;
        end springs 76 -> 54 g from 6 to 4 mm: docs/verification.md, docs/mechanics.md).
    rounding : float
        Corner rounding radius d, m (0: sharp corners, the default). With d > 0 every block
        corner is a circular arc of radius d tangent to its two edges (centred on the corner's
        bisector, d from both edge lines), as UDEC's rounding: a vertex contact's normal and
        opening are those of the rounded shapes, so a corner against a corner pushes along the
        line of the two arcs' centres, and a corner sliding past the end of a face turns round
        the face's rounded end instead of being held by the face's line (``rounding.py``,
        docs/mechanics.md). Face-to-face contacts of shared edges are unchanged. At most
        half the radius at which some block's edge would have no straight part left
        (ValueError naming the value otherwise; about 1 % of the block edge is UDEC's advice).
    deformable : dict, optional
        Deformable blocks (UDEC's): {block group name, or "*" for every block: zone size, m}.
        Each such block is meshed into constant-strain triangles no longer than the size
        (``zones.mesh_polygon`` in its body frame) with ``block_E`` (which must be finite for
        it), ``block_nu`` and the density; it keeps its rigid pose as a floating frame for the
        contacts, and its zones' displacement moves its contact points and takes their
        forces (``components/deformable.py``, docs/mechanics.md). Its contacts then have no
        series block compliance. None (default): every block rigid, the model bit for bit as
        without the option. Not with ``rounding`` or ``edge_elements`` (ValueError).
    zone_strength : dict, optional
        Mohr-Coulomb zones with a tension cut-off in the deformable blocks: {block group name,
        or "*": dict(cohesion=Pa, friction=deg, dilation=deg (default 0), tensile=Pa
        (default the apex c / tan phi))}, applied in the order given (a later entry wins for
        a block in both); the zones of other deformable blocks stay elastic (None, default:
        all elastic, bit for bit as without the option). Plane strain, in-plane principal
        stresses, perfectly plastic (``zone_plasticity``, docs/mechanics.md). Needs
        ``deformable``.
    """

    def __init__(self, blocks: BlockSystem, materials: dict, density, block_E=None,
                 block_nu=0.25, unbreakable=None, damping=0.8, safety=0.5, mass_scaling=False,
                 dt=None, search_margin=None, new_contact_material=None, history_every=100,
                 threads=1, kinetic_damping=0, edge_elements=False, rounding=0.0,
                 deformable=None, zone_strength=None, step_estimate="bound"):
        if not isinstance(blocks, BlockSystem):
            raise ValueError(f"blocks must be a BlockSystem, got {type(blocks).__name__}")
        if not (0.0 <= damping < 1.0):
            raise ValueError(f"damping must be in [0, 1), got {damping!r}")
        if not (0.0 < safety <= 1.0):
            raise ValueError(f"safety must be in (0, 1], got {safety!r}")
        if step_estimate not in STEP_ESTIMATES:
            raise ValueError(f"step_estimate must be one of {STEP_ESTIMATES}, got "
                             f"{step_estimate!r}")
        if step_estimate == "eigen" and (deformable is not None or rounding):
            raise ValueError("step_estimate='eigen' is for rigid blocks with sharp corners; "
                             f"got deformable={deformable!r}, rounding={rounding!r} (use "
                             "'bound')")
        if dt is not None and not (math.isfinite(dt) and dt > 0):
            raise ValueError(f"dt must be a finite time step > 0 s, got {dt!r}")
        import numba

        if not (isinstance(threads, (int, np.integer)) and
                1 <= threads <= numba.config.NUMBA_NUM_THREADS):
            raise ValueError(f"threads must be an integer in 1..{numba.config.NUMBA_NUM_THREADS}"
                             f", got {threads!r}")
        self.threads = int(threads)
        self.blocks = blocks
        self.materials = dict(materials)
        self.unbreakable = unbreakable
        self.table = material_table(blocks.material_names, self.materials, unbreakable)
        self.props = block_props(blocks, density)
        self.corners = rounding_bundle(self.props, rounding)     # rounding.Rounding
        self.rounding = self.corners.radius
        self.state = state_at_rest(blocks.centroid)
        nb = blocks.n_blocks
        self.block_E = self._per_block(block_E, np.inf, "block_E", lower=0.0)
        self.block_nu = self._per_block(block_nu, 0.25, "block_nu", lower=-1.0, upper=0.5)
        self.deformable = self._deformable_sizes(deformable, rounding, edge_elements)
        self.zone_strength = self._zone_strengths(zone_strength)
        self.zone_state = self._zone_bundle()     # components.deformable.Deformable
        self.damping = float(damping)
        if not (isinstance(kinetic_damping, (int, np.integer)) and kinetic_damping >= 0):
            raise ValueError(f"kinetic_damping must be a step interval >= 0 (0: off), got "
                             f"{kinetic_damping!r}")
        self.kinetic_damping = int(kinetic_damping)
        self.kinetic = np.zeros(3)     # Integrator.kinetic: kinetic-damping memory
        self.safety = float(safety)
        self.step_estimate = step_estimate
        self.mass_scaling = bool(mass_scaling)
        self.fixed_dt = dt
        med_r = float(np.median(self.props.radius)) if nb else 1.0
        self.search_margin = 0.05 * med_r if search_margin is None else float(search_margin)
        if not self.search_margin > 0:
            raise ValueError(f"search_margin must be > 0 m, got {search_margin!r}")
        self.search_enabled = True
        names = list(blocks.material_names)
        if new_contact_material is None:
            counts = np.bincount(blocks.edge_material, minlength=len(names)) if names else []
            new_contact_material = names[int(np.argmax(counts))] if names else None
        if new_contact_material is not None and new_contact_material not in names:
            names.append(new_contact_material)
            self.table = material_table(names, self.materials, unbreakable)
        self.new_contact_material = new_contact_material
        self.gravity = np.zeros(2)             # m/s^2 (components.Gravity)
        self.load = np.zeros((nb, 3))          # N/m, N m/m per block (components.Loads)
        self.servo_groups = []                 # (blocks, params row) (components.Servo)
        self.water = None                      # water.WaterTable (components.Water)
        self.water_faces = None                # exposed faces while there is water
        self.cables = support.no_cables()      # components.Cables (support.Cable)
        self.liners = support.no_liners()      # components.Liners (support.Liner)
        self.time = 0.0
        self.step = 0
        self.history = monitor.History(every=int(history_every))
        self.points = {}                       # name -> (block, local point (2,), start (2,))
        self.edge_elements = bool(edge_elements)
        self.contacts = detection.sort_for_locality(initial_contacts(self._contact_edges()))
        if not self.edge_elements:
            self.contacts.partner[:] = -1       # every contact its own spring
        self.props.surface_material[:] = surface_materials(self.contacts, len(blocks.vertices))
        self._set_contact_stiffness(np.arange(self.contacts.n))
        self.cracks = CrackLog(np.zeros((self.contacts.n + 16, 7)), np.zeros(1, np.int64))
        self.dt = None
        self._update_timestep()
        self.search()           # touching blocks that share no edge get (unbonded) contacts

    # ----------------------------------------------------------------- input helpers
    def _deformable_sizes(self, deformable, rounding, edge_elements):
        """The ``deformable`` option checked (ValueError naming a bad entry): a plain dict
        {group or "*": zone size m}, or None."""
        if deformable is None:
            return None
        if not isinstance(deformable, dict) or not deformable:
            raise ValueError(f"deformable must be a dict {{group name or '*': zone size m}} or "
                             f"None, got {deformable!r}")
        if rounding:
            raise ValueError(f"deformable blocks do not take corner rounding yet "
                             f"(rounding={rounding!r}): use rounding=0")
        if edge_elements:
            raise ValueError("deformable blocks do not take edge_elements=True yet")
        out = {}
        for name, size in deformable.items():
            self._check_option_group("deformable", name)
            if isinstance(size, bool) or not isinstance(size, (int, float, np.number)) or \
                    not (math.isfinite(size) and size > 0):
                raise ValueError(f"deformable: the zone size of {name!r} must be a finite "
                                 f"length > 0 m, got {size!r}")
            out[str(name)] = float(size)
        return out

    def _check_option_group(self, option, name):
        """ValueError naming ``name`` unless it is a block group or "*" (a per-group option)."""
        if name != "*" and name not in self.blocks.groups:
            raise ValueError(f"{option}: no block group {name!r}; groups are "
                             f"{sorted(self.blocks.groups)} (or '*' for every block)")

    def _zone_strengths(self, zone_strength):
        """The ``zone_strength`` option checked (ValueError naming a bad entry or value): a
        plain dict {group or "*": dict(cohesion=, friction=, dilation=, tensile=)}, or None."""
        if zone_strength is None:
            return None
        if not isinstance(zone_strength, dict) or not zone_strength:
            raise ValueError(f"zone_strength must be a dict {{group name or '*': dict(cohesion=Pa"
                             f", friction=deg, ...)}} or None, got {zone_strength!r}")
        if self.deformable is None:
            raise ValueError("zone_strength needs deformable blocks: pass deformable= to Model")
        out = {}
        for name, row in zone_strength.items():
            self._check_option_group("zone_strength", name)
            if not isinstance(row, dict) or any(isinstance(v, bool) or
                                                not isinstance(v, (int, float, np.number))
                                                for v in row.values()):
                raise ValueError(f"zone_strength: the entry of {name!r} must be a dict of "
                                 f"numbers (cohesion=Pa, friction=deg, ...), got {row!r}")
            strength_table(row, 1, f"zone_strength[{name!r}]")
            out[str(name)] = {k: float(v) for k, v in row.items()}
        return out

    def _zone_bundle(self):
        """The zones of the deformable blocks (empty bundle when none); their density is
        their block's (mass / area)."""
        if self.deformable is None:
            return zone_kernels.no_deformable()
        nb = self.n_blocks
        size = self._zone_sizes()
        bad = np.flatnonzero(np.isfinite(size) & ~np.isfinite(self.block_E))
        if bad.size:
            raise ValueError(f"deformable block {int(bad[0])} needs a finite block_E (Pa), got "
                             f"{self.block_E[bad[0]]!r}: pass block_E= to Model")
        rho = self.props.mass / self.blocks.area
        strength = strength_table(None, nb)
        for name, row in (self.zone_strength or {}).items():
            idx = np.arange(nb) if name == "*" else self.group(name)
            strength[idx] = strength_table(row, 1)
        return zone_kernels.deformable_bundle(self.props, size, self.block_E, self.block_nu, rho,
                                              strength, self.blocks.centroid,
                                              self.blocks.bounds())

    def _contact_edges(self):
        """The shared edges the initial contacts are made of: a deformable block's split into
        its zone size (``contacts.split_edges``), the others whole."""
        if self.deformable is None:
            return self.blocks
        size = np.nan_to_num(self._zone_sizes(), nan=np.inf)
        bs = self.blocks
        return split_edges(bs, np.minimum(size[bs.edge_block_a], size[bs.edge_block_b]))

    def _zone_sizes(self):
        """(nb,) the zone size of each block (m; the smallest its groups give), NaN: rigid."""
        size = np.full(self.n_blocks, np.nan)
        for name, h in self.deformable.items():
            idx = np.arange(self.n_blocks) if name == "*" else self.group(name)
            size[idx] = np.fmin(size[idx], h)
        return size

    @property
    def deformable_blocks(self) -> np.ndarray:
        """(nb,) bool: the blocks that have zones."""
        off = self.zone_state.point_offsets
        if off.shape[0] == 0:
            return np.zeros(self.n_blocks, bool)
        return np.diff(off) > 0

    def _per_block(self, value, default, name, lower=None, upper=None):
        nb = self.blocks.n_blocks
        arr = np.full(nb, default, dtype=np.float64) if value is None else \
            np.broadcast_to(np.asarray(value, dtype=np.float64), (nb,)).copy()
        bad = ~np.isfinite(arr) & ~np.isinf(arr) if value is None else ~np.isfinite(arr)
        if lower is not None:
            bad |= arr <= lower
        if upper is not None:
            bad |= arr >= upper
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(f"{name} of block {i} is {arr[i]!r}: out of range "
                             f"({lower}, {upper})")
        return arr

    def group(self, group) -> np.ndarray:
        """Block indices of a named group (str) or an index array."""
        if isinstance(group, str):
            if group not in self.blocks.groups:
                raise ValueError(f"no block group {group!r}; groups are "
                                 f"{sorted(self.blocks.groups)}")
            idx = np.asarray(self.blocks.groups[group], dtype=np.int64)
        else:
            idx = np.atleast_1d(np.asarray(group, dtype=np.int64))
        if idx.size and (idx.min() < 0 or idx.max() >= self.n_blocks):
            raise ValueError(f"block index out of range 0..{self.n_blocks - 1}")
        return idx

    @property
    def n_blocks(self) -> int:
        return self.blocks.n_blocks

    # ----------------------------------------------------------------- stiffness and dt
    def _set_contact_stiffness(self, rows):
        """kn, ks of contacts ``rows``: their material in series with the two blocks. Set when
        a contact is made (and when its material's stiffness changes); stresses are kept."""
        rows = np.asarray(rows, dtype=np.int64)
        if rows.size == 0:
            return
        c, st = self.contacts, self.state
        a, b, m = c.block_a[rows], c.block_b[rows], c.material[rows]
        xa = c.position(st.pos, st.rot)[rows]
        n = c.normal(st, self.corners)[rows]
        h_a = np.abs(((xa - st.pos[a]) * n).sum(axis=1))
        h_b = np.abs(((xa - st.pos[b]) * n).sum(axis=1))
        E = np.where(self.deformable_blocks, np.inf, self.block_E)   # zones: their own
        c.kn[rows], c.ks[rows] = series_stiffness(self.table.kn[m], self.table.ks[m], h_a, h_b,
                                                  E[a], self.block_nu[a],
                                                  E[b], self.block_nu[b])

    def _update_timestep(self):
        """Automatic step (and inertial masses with mass scaling) from the current contacts."""
        p, c = self.props, self.contacts
        w2 = stepper.frequency_bound(c, self.state, p)
        # a block without contacts may meet one: bound it by a contact of its own size made of
        # the new-contact material
        guard = np.zeros_like(w2)
        if self.new_contact_material is not None:
            mid = self.table.names.index(self.new_contact_material)
            kk = (self.table.kn[mid] + self.table.ks[mid]) * p.radius
            guard = 2.0 * (kk / p.mass + kk * p.radius ** 2 / p.inertia)
            w2 = np.maximum(w2, guard)
        kt, kr = support.support_stiffness(self)
        w2 = w2 + 2.0 * (kt / p.mass + kr / p.inertia)
        moving = (p.active > 0) & (p.fixity != (FIX_X | FIX_Y | FIX_ROT)) & (w2 > 0)
        scale = np.ones(self.n_blocks)
        target = None
        if self.mass_scaling and moving.any():
            target = float(np.median(w2[moving]))
            scale = np.maximum(1.0, w2 / target)
            w2 = w2 / scale
        p.inv_mass[:] = 1.0 / (p.mass * scale)
        p.inv_inertia[:] = 1.0 / (p.inertia * scale)
        w2max = float(w2[moving].max()) if moving.any() else 0.0
        if self.step_estimate == "eigen" and moving.any():
            w2max = self._eigen_omega2(moving, guard / scale,
                                       (kt / p.mass + kr / p.inertia) / scale)
        if not zone_kernels.is_empty(self.zone_state):
            w2max = max(w2max, self._zone_frequency(target))
        if w2max == 0 and support.has_nodes(self) and np.any(w2[p.active > 0] > 0):
            w2max = float(w2[p.active > 0].max())     # only the support moves
        if w2max > 0:
            support.set_node_masses(self, w2max)
        self.critical_dt = 2.0 / math.sqrt(w2max) if w2max > 0 else math.inf
        if self.fixed_dt is not None:
            self.dt = float(self.fixed_dt)
        elif math.isfinite(self.critical_dt):
            self.dt = self.safety * self.critical_dt
        elif self.dt is None:
            self.dt = None       # no contacts yet: cycle() will ask for a dt

    def _eigen_omega2(self, moving, guard, support_w2):
        """omega_max^2 for ``step_estimate="eigen"``: the largest eigenvalue of the contacts
        (``critical_step``), at least the new-contact guard of any free block that has no
        contact (a contact of its own size, as the bound takes it: it may meet one before
        the next search), plus the support elements' own bound (Weyl: the largest eigenvalue
        of a sum is at most the sum of the largest ones). A block's contacts within the
        search margin are all listed, so a block that has some needs no guard: a contact
        that closes before the next search is already counted, and the search that adds one
        recomputes the step. ``moving``: the free blocks with a bound (``_update_timestep``);
        ``guard``, ``support_w2``: per block, over the mass scale."""
        p, c = self.props, self.contacts
        alone = moving.copy()
        alone[c.block_a[:c.n]] = False
        alone[c.block_b[:c.n]] = False
        lam = critical_step.largest_omega2(c, self.state, p)
        lone = float(guard[alone].max()) if alone.any() else 0.0
        return max(lam, lone) + 2.0 * float(support_w2[moving].max())

    def _zone_frequency(self, target):
        """The gridpoints' largest omega^2 (Gershgorin: zones plus 2 (kn + ks) L of the
        contacts each takes a share of, over its mass); with mass scaling (``target``, the
        blocks' median bound) a gridpoint above the target gets that much more inertial
        mass, as a block does (when no block is free, the zones' own median is the target)."""
        z, p = self.zone_state, self.props
        w2 = zone_kernels.gridpoint_stiffness(z, self.contacts, self.state) / z.mass
        live = np.repeat(p.active > 0, np.diff(z.point_offsets))
        if target is None and self.mass_scaling and live.any():
            target = float(np.median(w2[live]))       # no free block: the zones' own median
        scale = np.ones_like(w2) if target is None else np.maximum(1.0, w2 / target)
        z.inv_mass[:] = 1.0 / (z.mass * scale)
        return float((w2 / scale)[live].max()) if live.any() else 0.0

    # ----------------------------------------------------------------- loading
    def set_gravity(self, g_level=1.0, g=STANDARD_GRAVITY, direction=(0.0, -1.0)):
        """Gravity of ``g_level`` x ``g`` (m/s^2) along ``direction`` (centrifuge: raise g_level)."""
        d = np.asarray(direction, dtype=np.float64)
        if not (np.all(np.isfinite(d)) and np.hypot(*d) > 0 and math.isfinite(g_level)
                and g_level >= 0):
            raise ValueError(f"bad gravity: g_level={g_level!r}, direction={direction!r}")
        self.gravity = g_level * g * d / np.hypot(*d)

    def fix(self, group, x=True, y=True, rotation=True, at=None):
        """Hold the chosen velocity components of a group at zero (a roller: ``x=False``);
        ``at``: where a deformable block is held (``set_velocity``)."""
        self.set_velocity(group, 0.0 if x else None, 0.0 if y else None,
                          0.0 if rotation else None, at=at)

    def free(self, group):
        """Release every prescribed velocity component of a group, and end any servo acting
        on its blocks."""
        idx = self.group(group)
        self.props.fixity[idx] = 0
        if not zone_kernels.is_empty(self.zone_state):
            z = self.zone_state
            z.held[idx] = 0
            z.point_held[np.repeat(np.isin(np.arange(self.n_blocks), idx),
                                   np.diff(z.point_offsets))] = 0
        self.servo_groups = [(g, prm) for g, prm in self.servo_groups
                             if not np.isin(g, idx).any()]
        self._update_timestep()

    def set_velocity(self, group, vx=None, vy=None, omega=0.0, at=None):
        """Prescribe velocities (m/s, rad/s) of a group; None leaves that component free.

        A deformable block (``deformable``) so held keeps its frame moving at the prescribed
        velocity in every component (the free ones at 0), and its gridpoints on the sides
        ``at`` of the model's bounding box ("left", "right", "bottom", "top", or a list of
        them; None: any side) are held in the prescribed directions of x and y; its other
        gridpoints carry the rest of its motion, under its whole load (a block with fewer than
        two gridpoints there is held whole; docs/mechanics.md, "Held deformable blocks")."""
        idx = self.group(group)
        for bit, col, v in ((FIX_X, 0, vx), (FIX_Y, 1, vy), (FIX_ROT, 2, omega)):
            if v is None:
                continue
            if not math.isfinite(v):
                raise ValueError(f"velocity component {col} is {v!r}")
            self.props.fixity[idx] |= bit
            self.props.velocity_bc[idx, col] = v
            if col < 2:
                self.state.vel[idx, col] = v
            else:
                self.state.omega[idx] = v
        self._hold_zones(idx, vx is not None, vy is not None, at)
        self._update_timestep()

    def _hold_zones(self, idx, x, y, at):
        """The deformable blocks among ``idx`` held in x and/or y at the box sides ``at``."""
        soft = idx[self.deformable_blocks[idx]]
        if soft.size == 0 or not (x or y):
            return
        zone_bc.hold_points(self.zone_state, soft, (FIX_X if x else 0) | (FIX_Y if y else 0),
                                 _sides(at))
        self.props.fixity[soft] = FIX_X | FIX_Y | FIX_ROT

    def apply_load(self, group, fx=0.0, fy=0.0, moment=0.0):
        """A constant total force (N/m) on a group, shared by mass; a moment (N m/m) per block."""
        idx = self.group(group)
        if not all(math.isfinite(v) for v in (fx, fy, moment)):
            raise ValueError(f"load must be finite, got {(fx, fy, moment)!r}")
        w = self.props.mass[idx] / self.props.mass[idx].sum()
        self.load[idx, 0] = fx * w
        self.load[idx, 1] = fy * w
        self.load[idx, 2] = moment

    def servo(self, group, force, direction=(0.0, -1.0), gain=None, v_max=None):
        """Move a group along ``direction`` so the reaction it feels stays at ``force`` (N/m).

        For a constant normal stress on a shear box or platen: ``force = stress x width``. The
        group's velocity along the direction is gain (force - reaction); the default gain moves
        the group by 1/10 of the force error's elastic displacement per step.
        """
        idx = self.group(group)
        d = np.asarray(direction, dtype=np.float64)
        d = d / np.hypot(*d)
        if not (math.isfinite(force) and force >= 0):
            raise ValueError(f"servo force must be finite and >= 0 N/m, got {force!r}")
        c = self.contacts
        ing = np.isin(c.block_a[:c.n], idx) ^ np.isin(c.block_b[:c.n], idx)
        k = float((c.kn[:c.n][ing] * c.length[:c.n][ing]).sum()) or 1.0
        gain = 0.1 / (k * self.dt) if gain is None else float(gain)
        v_max = math.inf if v_max is None else float(v_max)
        bits = (FIX_X if abs(d[0]) > 0 else 0) | (FIX_Y if abs(d[1]) > 0 else 0) | FIX_ROT
        self.props.fixity[idx] |= bits
        self.servo_groups.append((idx, np.array([d[0], d[1], force, gain, v_max])))

    def set_material(self, name, **changes):
        """Change a material between stages, e.g. ``set_material("flaw:*", tensile_strength=0)``.

        ``name`` is a key of the materials mapping (exact or pattern). A strength change touches
        only the material table: no stress, stiffness or position moves, broken contacts stay
        broken. A stiffness change (kn, ks) applies to the increments from now on of every
        contact of that material (its stresses are kept) and to new contacts.
        """
        if name not in self.materials:
            raise ValueError(f"no material {name!r}; materials are {sorted(self.materials)}")
        self.materials[name] = self.materials[name].with_strength(**changes)
        old = self.table
        self.table = material_table(old.names, self.materials, self.unbreakable)
        moved = np.flatnonzero((self.table.kn != old.kn) | (self.table.ks != old.ks))
        if moved.size:
            c = self.contacts
            self._set_contact_stiffness(np.flatnonzero(np.isin(c.material[:c.n], moved)))
            self._update_timestep()

    def set_contact_stress(self, sn, ts=0.0, rows=None):
        """Give contacts a stress (Pa, normal compression +, shear on B along t; scalars or
        arrays over ``rows``, default every live contact): an initial stress state. The law
        carries on from it by increments (``law.py``)."""
        c = self.contacts
        rows = np.arange(c.n) if rows is None else np.asarray(rows, dtype=np.int64)
        sn = np.broadcast_to(np.asarray(sn, dtype=np.float64), rows.shape)
        ts = np.broadcast_to(np.asarray(ts, dtype=np.float64), rows.shape)
        if not (np.all(np.isfinite(sn)) and np.all(np.isfinite(ts))):
            raise ValueError("contact stresses must be finite (Pa)")
        c.sn[rows], c.sn_elastic[rows], c.ts[rows] = sn, sn, ts

    def remove(self, group):
        """Excavate: remove a group's blocks and every contact they have. ValueError naming
        the group when none of its blocks is left (removed already, or an empty group)."""
        idx = self.group(group)
        p = self.props
        if not np.any(p.active[idx] > 0):
            name = repr(group) if isinstance(group, str) else f"of blocks {idx.tolist()}"
            raise ValueError(f"remove: group {name} has no blocks left to remove ("
                             f"{'it is empty' if idx.size == 0 else 'all removed already'})")
        p.active[idx] = 0
        p.fixity[idx] = FIX_X | FIX_Y | FIX_ROT
        p.velocity_bc[idx] = 0.0
        self.state.vel[idx] = 0.0
        self.state.omega[idx] = 0.0
        c = self.contacts
        keep = (p.active[c.block_a[:c.n]] > 0) & (p.active[c.block_b[:c.n]] > 0)
        self.contacts = c.take(np.flatnonzero(keep))
        if self.water is not None:
            self.water_faces = exposed_faces(self.blocks, p.active)
        self._update_timestep()

    def install(self, item):
        """Install support: a ``support.Cable`` (or bolt) or ``support.Liner``, or a list of
        them, stress-free in the present pose (``dem_core.components.support``)."""
        support.install(self, item)

    def write_vtk(self, path):
        """Write the present state for ParaView (.vtu: blocks, contacts, cracks, support;
        ``dem_core.output.vtk``, docs/output.md); returns the path."""
        from .output.vtk import write_vtk
        return write_vtk(self, path)

    def set_water(self, table):
        """Put a water table (``water.WaterTable``) on the model, or take it off (None):
        pressure on the contacts and exposed faces below it (``components.water``)."""
        if table is not None:
            table.check()
            self.water_faces = exposed_faces(self.blocks, self.props.active)
        else:
            self.water_faces = None
        self.water = table

    # ----------------------------------------------------------------- state: copies and files
    # What changes while a model runs (everything else is fixed at construction).
    _STATE = ("props", "state", "contacts", "cracks", "materials", "table", "gravity", "load",
              "servo_groups", "time", "step", "dt", "critical_dt", "kinetic", "history",
              "points", "search_enabled", "water", "water_faces", "cables", "liners",
              "zone_state")
    _SETTINGS = ("unbreakable", "damping", "safety", "step_estimate", "mass_scaling", "fixed_dt",
                 "search_margin", "new_contact_material", "threads", "kinetic_damping",
                 "edge_elements", "rounding", "deformable", "zone_strength")

    def snapshot(self) -> dict:
        """A copy of everything that changes while the model runs; ``restore`` returns to it."""
        return {k: copy.deepcopy(getattr(self, k)) for k in self._STATE}

    def restore(self, snapshot: dict):
        """Return to a ``snapshot`` (the snapshot stays usable)."""
        for k in self._STATE:
            setattr(self, k, copy.deepcopy(snapshot[k]))

    def save(self, path):
        """Write the whole model to ``path`` (.npz); ``Model.load`` resumes it bit-for-bit."""
        bundles = {"props": self.props, "state": self.state, "cracks": self.cracks,
                   "cables": self.cables, "liners": self.liners, "zone_state": self.zone_state}
        arrays = {"block_E": self.block_E, "block_nu": self.block_nu, "gravity": self.gravity,
                  "load": self.load, "kinetic": self.kinetic}
        meta = {"settings": {k: getattr(self, k) for k in self._SETTINGS},
                "clock": {k: getattr(self, k) for k in ("time", "step", "dt", "critical_dt",
                                                         "search_enabled")},
                "materials": {k: vars(m) for k, m in self.materials.items()},
                "table_names": self.table.names,
                "water": None if self.water is None else self.water.to_dict()}
        io.save_parts(path, self.blocks, bundles, self.contacts, arrays, meta,
                      self.servo_groups, self.points, self.history)

    @classmethod
    def load(cls, path) -> "Model":
        """A Model read from a file written by ``save``."""
        parts = io.load_parts(path)
        m = cls.__new__(cls)
        meta = parts["meta"]
        m.blocks = parts["blocks"]
        m.edge_elements = False                 # (files from before the options)
        m.rounding = 0.0
        m.deformable = None
        m.zone_strength = None
        m.step_estimate = "bound"
        for k, v in {**meta["settings"], **meta["clock"]}.items():
            setattr(m, k, v)
        m.materials = {k: Material(**v) for k, v in meta["materials"].items()}
        m.table = material_table(meta["table_names"], m.materials, m.unbreakable)
        m.props, m.state, m.cracks = (parts["bundles"][k] for k in ("props", "state", "cracks"))
        m.corners = rounding_bundle(m.props, m.rounding)
        m.cables = parts["bundles"].get("cables", support.no_cables())
        m.liners = parts["bundles"].get("liners", support.no_liners())
        m.zone_state = parts["bundles"].get("zone_state", zone_kernels.no_deformable())
        m.contacts = parts["contacts"]
        a = parts["arrays"]
        m.block_E, m.block_nu, m.gravity, m.load, m.kinetic = (
            a[k] for k in ("block_E", "block_nu", "gravity", "load", "kinetic"))
        m.servo_groups, m.points, m.history = (parts[k] for k in ("servo", "points", "history"))
        m.water = m.water_faces = None
        if meta.get("water") is not None:
            m.set_water(WaterTable.from_dict(meta["water"]))
        return m

    # ----------------------------------------------------------------- monitors
    def add_history_point(self, name, xy):
        """Record displacement and velocity of the body point at ``xy`` (m) as ``name``."""
        xy = np.asarray(xy, dtype=np.float64)
        b = detection.block_containing(self.props, self.state.pos, self.state.rot, xy)
        local = xy - self.state.pos[b]
        c, s = self.state.rot[b]
        self.points[name] = (b, np.array([c * local[0] + s * local[1],
                                          -s * local[0] + c * local[1]]), xy.copy())

    def point_motion(self, name):
        """(ux, uy, vx, vy) of a history point now, m and m/s (on a deformable block, the
        frame's motion plus its zones' at the point)."""
        b, r, x0 = self.points[name]
        c, s = self.state.rot[b]
        rx, ry = r
        zvx = zvy = 0.0
        if not zone_kernels.is_empty(self.zone_state):    # a deformable block: its zones too
            ux, uy, zvx, zvy = zone_bc.point_motion(self.zone_state, b, r)
            rx, ry = rx + ux, ry + uy
        x = self.state.pos[b] + np.array([c * rx - s * ry, s * rx + c * ry])
        w = self.state.omega[b]
        v = self.state.vel[b] + w * np.array([-(x[1] - self.state.pos[b, 1]),
                                              x[0] - self.state.pos[b, 0]])
        v += np.array([c * zvx - s * zvy, s * zvx + c * zvy])
        return x[0] - x0[0], x[1] - x0[1], v[0], v[1]

    def unbalanced_ratio(self) -> float:
        """sum |unbalanced force| / sum |forces acting| (``monitor.unbalanced_ratio``); the
        deformable blocks' gridpoints add their unbalanced (non-rigid) forces to the sum, so
        a model is in equilibrium when its frames and its zones are."""
        p, c = self.props, self.contacts
        num, den = support.unbalanced(self)
        if not zone_kernels.is_empty(self.zone_state):
            zn, zd = zone_bc.unbalanced(self.zone_state, p.active, self.gravity)
            num, den = num + zn, den + zd
        return monitor.unbalanced_ratio(self.state.force, p.mass, self.gravity, self.load,
                                        p.fixity, p.active, c.n, c.block_a, c.block_b,
                                        c.length, c.sn, c.ts, num, den)

    def kinetic_energy(self) -> float:
        """J/m: the blocks' (real masses), plus the deformable blocks' zones' motion in
        their frames."""
        p = self.props
        ke = monitor.kinetic_energy(self.state.vel, self.state.omega, p.mass, p.inertia,
                                    p.active)
        if not zone_kernels.is_empty(self.zone_state):
            ke += zone_kernels.kinetic_energy(self.zone_state)
        return ke

    def strain_energy(self) -> float:
        """J/m: the contact springs', plus the deformable blocks' zones'."""
        c = self.contacts
        w = monitor.strain_energy(c)
        if not zone_kernels.is_empty(self.zone_state):
            w += zone_kernels.strain_energy(self.zone_state)
        return w

    def gravity_energy(self) -> float:
        """Potential of gravity relative to the initial positions, J/m (the blocks' frames and
        the deformable blocks' gridpoints in them)."""
        a = self.props.active > 0
        du = self.state.pos[a] - self.state.pos0[a]
        e = float(-(self.props.mass[a] * (du @ self.gravity)).sum())
        z = self.zone_state
        if not zone_kernels.is_empty(z):     # the zones' own displacement (a held block's)
            counts = np.diff(z.point_offsets)
            owner = np.repeat(np.arange(self.n_blocks), counts)
            live = a[owner]
            c, s = self.state.rot[owner].T
            u = z.x - z.x0
            ux, uy = c * u[:, 0] - s * u[:, 1], s * u[:, 0] + c * u[:, 1]
            e -= float((z.mass * (ux * self.gravity[0] + uy * self.gravity[1]))[live].sum())
        return e

    def displacement(self) -> np.ndarray:
        """(nb, 2) centroid displacement from the start, m."""
        return self.state.pos - self.state.pos0

    def crack_log(self) -> dict:
        """Every failure so far: time (s), x, y (m), mode (1 tension, 2 shear), blocks, material."""
        n = min(int(self.cracks.count[0]), self.cracks.rows.shape[0])
        r = self.cracks.rows[:n]
        return {"time": r[:, 0].copy(), "x": r[:, 1].copy(), "y": r[:, 2].copy(),
                "mode": r[:, 3].astype(np.int8), "block_a": r[:, 4].astype(np.int64),
                "block_b": r[:, 5].astype(np.int64),
                "material": [self.table.names[int(m)] for m in r[:, 6]]}

    def crack_counts(self) -> dict:
        mode = self.cracks.rows[:int(self.cracks.count[0]), 3]
        return {"tension": int((mode == 1).sum()), "shear": int((mode == 2).sum())}

    def _record(self):
        row = {"step": self.step, "time": self.time, "ratio": self.unbalanced_ratio(),
               "kinetic_energy": self.kinetic_energy()}
        row.update({f"cracks_{k}": v for k, v in self.crack_counts().items()})
        for name in self.points:
            ux, uy, vx, vy = self.point_motion(name)
            row.update({f"{name}.ux": ux, f"{name}.uy": uy, f"{name}.vx": vx, f"{name}.vy": vy})
        self.history.record(row)

    # ----------------------------------------------------------------- running
    def _components(self):
        """The force component bundles of the step, empty where the scene has none."""
        return (gravity_bundle(self.gravity), loads_bundle(self.load),
                water_bundle(self.water, self.contacts, self.state, self.table.names,
                             self.water_faces), self.cables, self.liners,
                servo_bundle(self.servo_groups))

    def _parallel(self, parts):
        """Scratch and the block -> contact table for the threaded kernel (empty: serial);
        ``parts`` the component bundles and the zones (``_run``)."""
        if self.threads <= 1:
            return no_parallel()
        # the one-region step (gravity the only other force) pays from fewer contacts
        fewest = (region.MIN_CONTACTS if stepper.only_gravity(*parts[1:])
                  else parallel.MIN_CONTACTS)
        if self.contacts.n < fewest:
            return no_parallel()
        import numba
        numba.set_num_threads(self.threads)
        return parallel_bundle(self.contacts, self.n_blocks, self.threads,
                               self.edge_elements)

    def _integrator(self):
        half = 0.5 * self.search_margin if self.search_enabled else math.inf
        return Integrator(float(self.dt), self.damping, half, self.kinetic_damping, self.kinetic,
                          self.edge_elements)

    def _run(self, n):
        support.set_controls(self)
        self.zone_state.control[:] = (self.dt, self.damping, *self.gravity)
        blocks = (self.state, self.props, self.contacts, self.table.strength_array(),
                  self.cracks, self.corners)
        parts = (*self._components(), self.zone_state)
        par = self._parallel(parts)
        if par.offsets.shape[0] == 0:
            kernel, args = stepper.run_steps, (n, self.time, self._integrator(), *blocks, *parts)
        else:
            kernel = stepper.run_steps_threaded
            args = (n, self.time, self._integrator(), *blocks, par, *parts)
        steps, self.time, status, bad = compiled(kernel, args)(*args)
        self.step += steps
        if status == stepper.UNSTABLE:
            raise ModelUnstable(self._diagnose(bad))
        if status == stepper.NEED_SEARCH:
            self.search()
        return steps

    def cycle(self, n: int):
        """Advance ``n`` steps (histories recorded every ``history.every`` steps); ``n`` a
        whole number >= 0 (ValueError naming it otherwise: negative, fractional, NaN)."""
        whole = (isinstance(n, (int, np.integer)) and not isinstance(n, bool)) or (
            isinstance(n, (float, np.floating)) and math.isfinite(n) and float(n).is_integer())
        if not whole or n < 0:
            raise ValueError(f"cycle: the number of steps must be a whole number >= 0, got {n!r}")
        if self.dt is None:
            raise ValueError("no contacts to set the time step: pass dt= to Model")
        n = int(n)
        done = 0
        while done < n:
            every = self.history.every
            chunk = min(n - done, every - self.step % every)
            done += self._run(chunk)
            if self.step % every == 0:
                self._record()

    def solve(self, ratio=1e-5, max_steps=100_000, check_every=None, failure_displacement=None,
              creep=None, trace=None, settle=False):
        """Cycle until the unbalanced ratio <= ``ratio`` or ``max_steps``; returns a SolveResult.

        ``failure_displacement`` (m): stop as "failed" once a block has moved this far during
        the solve. ``creep`` (m, default 1e-3 of the median block radius): displacement
        increments below this do not count as movement in the end-of-run test
        (``monitor.verdict``). ``trace``: optional (steps, displacements) lists, each starting
        with 0, that the checks are appended to (still readable after a ``ModelUnstable``).
        ``settle``: stop early as "settled" (``monitor.settled``, ``monitor.settle_window``).
        """
        if not (ratio > 0):
            raise ValueError(f"ratio must be > 0, got {ratio!r}")
        check = int(check_every or max(self.history.every, 100))
        creep = 1e-3 * float(np.median(self.props.radius)) if creep is None else creep
        start = self.state.pos.copy()
        act = self.props.active > 0
        steps, disp = trace if trace is not None else ([0], [0.0])
        cracks = [int(self.cracks.count[0])]
        done, r = 0, math.inf
        while done < max_steps:
            k = min(check, max_steps - done)
            self.cycle(k)
            done += k
            r = self.unbalanced_ratio()
            d = float(np.hypot(*(self.state.pos[act] - start[act]).T).max()) if act.any() else 0.0
            steps.append(done)
            disp.append(d)
            if r <= ratio:
                return monitor.SolveResult("equilibrium", done, r, max(disp),
                                           f"ratio {r:.3g} <= {ratio:.3g}")
            if failure_displacement is not None and d > failure_displacement:
                return monitor.SolveResult("failed", done, r, d,
                                           f"a block moved {d:.3g} m > {failure_displacement} m")
            cracks.append(int(self.cracks.count[0]))
            window = monitor.settle_window(max_steps, creep)
            if settle and monitor.settled(steps, disp, cracks, *window):
                return monitor.SolveResult("settled", done, r, max(disp), monitor.SETTLED)
        v, why = monitor.verdict(steps, disp, creep)
        return monitor.SolveResult(v, done, r, max(disp), why)

    def search(self):
        """Contact search now: keep surviving contacts (with history), add new ones.

        A new contact starts stress-free at touching: its elastic normal stress is -kn times
        its opening when found (a contact found open carries nothing until it closes)."""
        old_n = self.contacts.n
        new_id = (self.table.names.index(self.new_contact_material)
                  if self.new_contact_material is not None else -1)
        self.contacts, n_new = detection.update_contacts(self.contacts, self.state, self.props,
                                                         self.table, new_id,
                                                         self.search_margin, self.corners)
        if n_new:
            c = self.contacts
            rows = np.arange(c.n - n_new, c.n)
            self._set_contact_stiffness(rows)
            # (with deformable blocks, at the deformed points: a new contact starts unstressed)
            c.un[rows], c.us[rows] = detection.displacements(c, self.state, rows, self.corners,
                                                             self.zone_state)
            c.sn_elastic[rows] = -c.kn[rows] * c.un[rows]
            self.contacts = detection.sort_for_locality(c)
        self.state.pos_search[:] = self.state.pos
        self.state.theta_search[:] = self.state.theta
        if n_new or self.contacts.n != old_n:
            self._update_timestep()

    # a block whose contacts overlap by more than this fraction of its width is squeezed
    SQUEEZED = 0.1

    def _diagnose(self, b) -> str:
        c = self.contacts
        mine = np.flatnonzero((c.block_a[:c.n] == b) | (c.block_b[:c.n] == b))
        kmax = float(c.kn[mine].max()) if mine.size else 0.0
        area = float(self.blocks.area[b])
        med = float(np.median(self.blocks.area))
        cause = []
        if area < 1e-3 * med:
            cause.append(f"a sliver (area {area:.3g} m^2 vs median {med:.3g}): merge it or use "
                         "mass_scaling=True")
        width = area / (2.0 * float(self.props.radius[b]))   # a thin block's width
        overlap = float(-c.un[mine].min()) if mine.size else 0.0
        if overlap > self.SQUEEZED * width:
            cause.append(
                f"a squeezed block: its contacts overlap by up to {overlap * 1e3:.3g} mm, "
                f"{overlap / width:.2g} of its width ({width:.3g} m = area / (2 radius)), at "
                f"normal stresses up to {float(c.sn[mine].max()) / 1e6:.3g} MPa; the contacts "
                "are far too soft for that stress (a thin block wedged at a joint crossing): "
                "stiffen those contacts, or excavate such blocks (e.g. area / radius^2 < 0.3) "
                "before loading")
        if self.fixed_dt is not None and self.fixed_dt > self.critical_dt:
            cause.append(f"the fixed dt {self.fixed_dt:.3g} s exceeds the critical step "
                         f"{self.critical_dt:.3g} s: let the model choose dt")
        if mine.size and c.ks[mine].max() > 10 * c.kn[mine].min():
            cause.append("a large ks/kn ratio: lower the safety factor")
        cause = cause or [f"the time step {self.dt:.3g} s is too large for the stiffness "
                          f"(kn up to {kmax:.3g} Pa/m): lower safety"]
        return (f"unstable at step {self.step}, t = {self.time:.6g} s: block {b} "
                f"(centroid {self.state.pos[b].round(6).tolist()}, {mine.size} contacts, "
                f"velocity {self.state.vel[b].tolist()}) moved too far in one step or became "
                f"NaN. Likely cause: {'; '.join(cause)}.")


def _sides(at):
    """``at`` of ``set_velocity`` checked: None, a side name or a list of them."""
    if at is None:
        return None
    names = [at] if isinstance(at, str) else list(at)
    bad = [n for n in names if n not in zone_bc.BOX_SIDES]
    if bad or not names:
        raise ValueError(f"at must name sides of the model's box {sorted(zone_bc.BOX_SIDES)}"
                         f", got {at!r}")
    return names
