"""The Model: the driver of a DEM damage model, its verbs and its run loop.

    model = Model(blocks, {"flaw:*": Material(kn=40e9, ks=20e9, tensile_strength=1.1e6,
                                              cohesion=1.2e6, friction=37)}, density=2400)
    model.fix("bottom")
    model.set_gravity(1.0)
    result = model.solve(ratio=1e-5, max_steps=50_000)   # result.verdict == "equilibrium"

The class keeps the bundles (``step.world``), resolves names and runs the step (``step.run``)
in chunks, Python between chunks; the rest are functions of the bundles it calls
(docs/architecture.md, "The driver").
"""
from __future__ import annotations

import copy
import math

import numpy as np

from .components import exposed_faces, gravity_bundle, loads_bundle, servo_bundle, water_bundle
from .components.boundaries import prescribe, remove_blocks, set_stress, spread_load
from .components.servo import servo_row
from .components import support
from .contact import softening
from .contact.contacts import initial_contacts, surface_materials
from .contact.detection import sort_for_locality
from .contact.materials import Material, material_table
from .contact.rounding import rounding_bundle
from .contact.stiffness import set_contact_stiffness
from .contact.update import search_contacts
from .deformable import held as zone_bc
from .deformable import setup as zone_setup
from .geometry.blocks import BlockSystem, group_blocks
from .jit_cache import compiled, first_run_notice
from .output import energy, io, monitor
from .settings import (SolverOptions, SolveSettings, material_names, new_contact_material,
                       per_block, search_margin)
from .step import relaxation, run as stepper
from .step.state import CrackLog, Integrator, block_props, state_at_rest
from .step.threads import parallel
from .step.timestep import choose_timestep
from .step.world import Parts, World
from .units import STANDARD_GRAVITY
from .workflow.plausibility import G_LEVEL_MAX
from .workflow.response import measure_response
from .workflow.solve import solve
from .workflow.water import WaterTable

__all__ = ["Model", "ModelUnstable", "STANDARD_GRAVITY"]

# options whose change moves the time step (``set_options``)
_STEP_OPTIONS = {"safety", "dt", "mass_scaling", "step_estimate"}


class ModelUnstable(RuntimeError):
    """The run blew up (NaN or runaway motion); the message names the block and likely cause."""


class Model:
    """A DEM damage-model scene and its state: ``blocks`` a BlockSystem, ``materials``
    {material name or fnmatch pattern ("flaw:*"): Material}, ``density`` kg/m^3 (float or
    (nb,)), and the ``settings.SolverOptions`` (``options`` and/or its fields as keywords,
    ``damping=0.8, edge_elements=True``), validated before any compute; read back as
    attributes (``model.damping``), changed with ``set_options``."""

    def __init__(self, blocks: BlockSystem, materials: dict, density, options=None, **changes):
        if not isinstance(blocks, BlockSystem):
            raise ValueError(f"blocks must be a BlockSystem, got {type(blocks).__name__}")
        opts = (options or SolverOptions()).replace(**changes)
        first_run_notice(stepper.run_steps)        # a minute of compiling, not a hang
        groups = blocks.groups
        self.blocks = blocks
        self.materials = dict(materials)
        self.props = block_props(blocks, density)
        self.corners = rounding_bundle(self.props, opts.rounding)     # contact.rounding
        self.state = state_at_rest(blocks.centroid)
        self.block_E = per_block(opts.block_E, np.inf, "block_E", blocks.n_blocks, 0.0)
        self.block_nu = per_block(opts.block_nu, 0.25, "block_nu", blocks.n_blocks, -1.0, 0.5)
        sizes = zone_setup.deformable_sizes(opts.deformable, groups, opts.rounding,
                                            opts.edge_elements)
        strengths = zone_setup.zone_strengths(opts.zone_strength, sizes, groups)
        self.options = opts.replace(deformable=sizes, zone_strength=strengths,
                                    search_margin=search_margin(opts, self.props),
                                    new_contact_material=new_contact_material(opts, blocks))
        self.table = material_table(material_names(blocks, self.options), self.materials,
                                    opts.unbreakable)
        self.zone_state = zone_setup.zone_bundle(blocks, self.props, sizes,
                                                 (self.block_E, self.block_nu), strengths,
                                                 self.group)
        self.kinetic = np.zeros(8)             # Integrator.kinetic: kinetic-damping memory
        self.energy_bank = np.zeros(len(energy.BANK))   # output.energy: dropped work, origin
        self.search_enabled = True
        self.response_steps = None             # N_r, steps (workflow.response), once measured
        self.in_motion = False                 # the last judged solve did not end at rest
        self.measured_steps = 0                # steps run by response-time measurements
        self.gravity = np.zeros(2)             # m/s^2 (components.Gravity)
        self.load = np.zeros((blocks.n_blocks, 3))   # N/m, N m/m per block (components.Loads)
        self.servo_groups = []                 # (blocks, params row) (components.Servo)
        self.water = None                      # workflow.water.WaterTable (components.Water)
        self.water_faces = None                # exposed faces while there is water
        self.cables = support.no_cables()      # components.Cables (support.Cable)
        self.liners = support.no_liners()      # components.Liners (support.Liner)
        self.time, self.step, self.dt, self.critical_dt = 0.0, 0, None, math.inf
        self.history = monitor.History(every=int(opts.history_every))
        self.points = {}                       # name -> (block, local point (2,), start (2,))
        edges = zone_setup.contact_edges(blocks, sizes, self.group)
        self.contacts = sort_for_locality(initial_contacts(edges))
        if not opts.edge_elements:
            self.contacts.partner[:] = -1       # every contact its own spring
        self.props.surface_material[:] = surface_materials(self.contacts, len(blocks.vertices))
        self._stiffen(np.arange(self.contacts.n))
        softening.check_contacts(self.table, self.contacts)
        softening.warn_unresolved(self.characteristic_lengths())
        self.cracks = CrackLog(np.zeros((self.contacts.n + 16, 7)), np.zeros(1, np.int64))
        self.update_timestep()
        self.search()           # touching blocks that share no edge get (unbonded) contacts

    # ----------------------------------------------------------------- names and records
    def group(self, group) -> np.ndarray:
        """Block indices of a named group (str) or an index array (``blocks.group_blocks``)."""
        return group_blocks(self.blocks, group)

    @property
    def n_blocks(self) -> int:
        return self.blocks.n_blocks

    @property
    def deformable_blocks(self) -> np.ndarray:
        """(nb,) bool: the blocks that have zones."""
        off = self.zone_state.point_offsets
        return np.diff(off) > 0 if off.shape[0] else np.zeros(self.n_blocks, bool)

    def world(self) -> World:
        """The step's World record of the present bundles (``step.world``)."""
        return World(self.state, self.props, self.contacts, self.table.strength_array(),
                     self.cracks, self.corners, self.zone_state)

    def parts(self) -> Parts:
        """The force components of the step, empty where the scene has none."""
        return Parts(gravity_bundle(self.gravity), loads_bundle(self.load),
                     water_bundle(self.water, self.contacts, self.state, self.table.names,
                                  self.water_faces, self.corners), self.cables, self.liners,
                     servo_bundle(self.servo_groups))

    def integrator(self) -> Integrator:
        half = 0.5 * self.search_margin if self.search_enabled else math.inf
        return Integrator(float(self.dt), self.damping, half, self.kinetic_damping, self.kinetic,
                          self.edge_elements, self.kinetic_adaptive)

    def threads_bundle(self, parts) -> parallel.Parallel:
        """Scratch and the block -> contact table of the threaded step (empty: serial)."""
        return parallel.threads_bundle(self.contacts, self.n_blocks, self.threads,
                                       self.edge_elements,
                                       stepper.only_gravity(parts, self.zone_state))

    # ----------------------------------------------------------------- options and the step
    def set_options(self, **changes):
        """Change solver options between runs, e.g. ``set_options(damping=0.0)`` (validated;
        ``SolverOptions.FIXED_AT_BUILD`` refused); the time step follows."""
        fixed = SolverOptions.FIXED_AT_BUILD & set(changes)
        if fixed:
            raise ValueError(f"set_options: {sorted(fixed)} are fixed when the model is "
                             "built; build a new Model")
        self.options = self.options.replace(**changes)
        if _STEP_OPTIONS & set(changes):
            self.update_timestep()

    def enable_search(self, on=True):
        """Turn the contact search on or off (off: the contacts stay as they are)."""
        self.search_enabled = bool(on)

    def update_timestep(self):
        """Recompute the time step and the inertial masses from the present bundles."""
        self.dt, self.critical_dt = choose_timestep(self.world(), self.cables, self.liners,
                                                    self.options, self.table, self.dt)

    def _moduli(self):
        """(E, nu) per block for contact stiffness in series (a deformable block's zones
        carry their own elasticity: E = inf)."""
        return np.where(self.deformable_blocks, np.inf, self.block_E), self.block_nu

    def _stiffen(self, rows):
        set_contact_stiffness(self.contacts, self.state, self.corners, self.table,
                              self._moduli(), rows)

    # ----------------------------------------------------------------- loading
    def set_gravity(self, g_level=1.0, g=STANDARD_GRAVITY, direction=(0.0, -1.0)):
        """Gravity of ``g_level`` x ``g`` (m/s^2) along ``direction`` (centrifuge: raise g_level)."""
        d = np.asarray(direction, dtype=np.float64)
        if not (np.all(np.isfinite(d)) and np.hypot(*d) > 0 and math.isfinite(g_level)
                and 0 <= g_level <= G_LEVEL_MAX):
            raise ValueError(f"bad gravity: g_level={g_level!r} (0 to {G_LEVEL_MAX:g}), "
                             f"direction={direction!r}")
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
        zone_bc.release(self.zone_state, idx)
        self.servo_groups = [(g, prm) for g, prm in self.servo_groups
                             if not np.isin(g, idx).any()]
        self.update_timestep()

    def set_velocity(self, group, vx=None, vy=None, omega=0.0, at=None):
        """Prescribe velocities (m/s, rad/s) of a group; None leaves that component free. A
        deformable block is held at its gridpoints on the box sides ``at`` (``held.hold``)."""
        idx = self.group(group)
        prescribe(self.props, self.state, idx, (vx, vy, omega))
        zone_bc.hold(self.zone_state, self.props, idx[self.deformable_blocks[idx]],
                     (vx is not None, vy is not None), at)
        self.update_timestep()

    def apply_load(self, group, fx=0.0, fy=0.0, moment=0.0):
        """A constant total force (N/m) on a group, shared by mass; a moment (N m/m) per block."""
        spread_load(self.load, self.props.mass, self.group(group), (fx, fy, moment))

    def servo(self, group, force, direction=(0.0, -1.0), gain=None, v_max=None):
        """Move a group along ``direction`` so the reaction it feels stays at ``force`` (N/m):
        velocity = gain (force - reaction); the default gain moves the group by 1/10 of the
        force error's elastic displacement per step (``components.servo``)."""
        idx = self.group(group)
        row, bits = servo_row(self.contacts, idx, force, direction, gain, v_max, self.dt)
        self.props.fixity[idx] |= bits
        self.servo_groups.append((idx, row))

    def set_material(self, name, **changes):
        """Change a material between stages, e.g. ``set_material("flaw:*", tensile_strength=0)``:
        a strength change moves no stress; a stiffness change acts on later increments."""
        if name not in self.materials:
            raise ValueError(f"no material {name!r}; materials are {sorted(self.materials)}")
        self.materials[name] = self.materials[name].with_strength(**changes)
        old = self.table
        self.table = material_table(old.names, self.materials, self.unbreakable)
        moved = np.flatnonzero((self.table.kn != old.kn) | (self.table.ks != old.ks))
        if moved.size:
            c = self.contacts
            self._stiffen(np.flatnonzero(np.isin(c.material[:c.n], moved)))
            self.update_timestep()
        softening.check_contacts(self.table, self.contacts)

    def set_contact_stress(self, sn, ts=0.0, rows=None):
        """Give contacts a stress (Pa, normal compression +, shear on B along t; scalars or
        arrays over ``rows``, default every live contact): an initial stress state."""
        set_stress(self.contacts, rows, sn, ts)

    def remove(self, group):
        """Excavate: remove a group's blocks and every contact they have. ValueError naming
        the group when none of its blocks is left (removed already, or an empty group)."""
        p = self.props
        self.contacts = remove_blocks(p, self.state, self.contacts, self.group(group), group)
        energy.reset_origin(self)       # the removed blocks take their energy with them
        if self.water is not None:
            self.water_faces = exposed_faces(self.blocks, p.active)
        self.update_timestep()
        if not self.in_motion:          # a new structure: its response time is measured anew,
            self.response_steps = None  # unless a mechanism is under way (workflow.response)

    def install(self, item):
        """Install support: a ``support.Cable`` (or bolt) or ``support.Liner``, or a list of
        them, stress-free in the present pose (``components.support``)."""
        self.cables, self.liners = support.installed(self, item)
        self.update_timestep()

    def set_water(self, table):
        """Put a water table (``workflow.water.WaterTable``) on the model, or take it off
        (None): pressure on the contacts and exposed faces below it (``components.water``)."""
        if table is not None:
            table.check()
        self.water_faces = None if table is None else exposed_faces(self.blocks,
                                                                     self.props.active)
        self.water = table

    def write_vtk(self, path):
        """Write the present state for ParaView (``output.vtk``, docs/output.md)."""
        from .output.vtk import write_vtk
        return write_vtk(self, path)

    # ----------------------------------------------------------------- copies and files
    def snapshot(self) -> dict:
        """A copy of everything that changes while the model runs; ``restore`` returns to it."""
        return {k: copy.deepcopy(getattr(self, k)) for k in io.RUNNING}

    def restore(self, snapshot: dict):
        """Return to a ``snapshot`` (the snapshot stays usable)."""
        for k in io.RUNNING:
            setattr(self, k, copy.deepcopy(snapshot[k]))

    def save(self, path):
        """Write the whole model to ``path`` (.npz, ``output.io``); ``load`` resumes it bit
        for bit."""
        io.write_model(path, self)

    @classmethod
    def load(cls, path) -> "Model":
        """A Model read from a file written by ``save`` (an older format is converted, or
        refused with a message naming the file and its version)."""
        m = cls.__new__(cls)
        for k, v in io.read_model(path, Material, WaterTable.from_dict).items():
            setattr(m, k, v)
        return m

    # ----------------------------------------------------------------- measures
    def add_history_point(self, name, xy):
        """Record displacement and velocity of the body point at ``xy`` (m) as ``name``."""
        self.points[name] = monitor.body_point(self.world(), xy)

    def point_motion(self, name):
        """(ux, uy, vx, vy) of a history point now, m and m/s (``monitor.point_motion``)."""
        return monitor.point_motion(self.world(), self.points[name])

    def kinetic_stops(self) -> dict:
        """Kinetic-damping stops so far: ``stops``, ``late`` (after the peak: the checks were
        too sparse for the motion, ``step.relaxation``) and ``every`` (the check interval
        now, steps)."""
        k = self.kinetic
        adapted = self.kinetic_adaptive and k[relaxation.EVERY] > 0
        every = k[relaxation.EVERY] if adapted else self.kinetic_damping
        return {"stops": int(k[relaxation.STOPS]), "late": int(k[relaxation.LATE_STOPS]),
                "every": int(every)}

    def restart_kinetic_interval(self):
        """Check the kinetic energy every ``kinetic_damping`` steps again (a new load step:
        ``workflow.solve`` calls it; ``step.relaxation``)."""
        self.kinetic[relaxation.EVERY] = 0.0

    def unbalanced_ratio(self) -> float:
        """The unbalanced-force ratio of blocks, zones and support (``monitor.model_ratio``)."""
        return monitor.model_ratio(self.world(), self.gravity, self.load, self.cables,
                                   self.liners)

    def kinetic_energy(self) -> float:
        """J/m (``monitor.model_kinetic_energy``)."""
        return monitor.model_kinetic_energy(self.world())

    def strain_energy(self) -> float:
        """J/m (``monitor.model_strain_energy``)."""
        return monitor.model_strain_energy(self.world())

    def gravity_energy(self) -> float:
        """J/m, relative to the initial positions (``monitor.gravity_energy``)."""
        return monitor.gravity_energy(self.world(), self.gravity)

    def characteristic_lengths(self) -> dict:
        """{material: (l_ch_I, l_ch_II, block spacing d)}, m, of the softening materials
        (``contact.softening.characteristic_lengths``)."""
        return softening.characteristic_lengths(self.table, self.contacts, self.state.pos)

    def energy(self) -> dict:
        """The energy account, J/m: external work, kinetic, strain, fracture, friction and
        damping terms and their balance (``output.energy.energy_account``)."""
        return energy.energy_account(self)

    def reset_energy(self):
        """Start the energy account now (``output.energy.reset_origin``)."""
        energy.reset_origin(self)

    def displacement(self) -> np.ndarray:
        """(nb, 2) centroid displacement from the start, m."""
        return self.state.pos - self.state.pos0

    def crack_log(self) -> dict:
        """Every failure so far (``monitor.crack_log``)."""
        return monitor.crack_log(self.cracks, self.table.names)

    def crack_counts(self) -> dict:
        return monitor.crack_counts(self.cracks)

    def diagnose(self, block) -> str:
        """Why ``block`` went unstable and the fix (``monitor.diagnose``)."""
        return monitor.diagnose(self.world(), self.blocks.area, block, dict(
            step=self.step, time=self.time, dt=self.dt, critical_dt=self.critical_dt,
            fixed_dt=self.fixed_dt))

    def _record(self):
        self.history.record(monitor.history_row(self.step, self.time, self.unbalanced_ratio(),
                                                self.kinetic_energy(), self.crack_counts(),
                                                {n: self.point_motion(n) for n in self.points},
                                                self.energy()))

    # ----------------------------------------------------------------- running
    def _run(self, n):
        world, parts = self.world(), self.parts()
        par = self.threads_bundle(parts)
        if par.offsets.shape[0] == 0:
            if self.options.deformable is None:    # rigid: the zones' code is not compiled
                world = world._replace(zones=None)
            kernel, args = stepper.run_steps, (n, self.time, self.integrator(), world, parts)
        else:
            kernel = stepper.run_steps_threaded
            args = (n, self.time, self.integrator(), world, parts, par)
        steps, self.time, status, bad = compiled(kernel, args)(*args)
        self.step += steps
        if status == stepper.UNSTABLE:
            raise ModelUnstable(self.diagnose(bad))
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
        n, done = int(n), 0
        while done < n:
            every = self.history.every
            done += self._run(min(n - done, every - self.step % every))
            if self.step % every == 0:
                self._record()

    def solve(self, settings=None, *, check_every=None, trace=None, **changes):
        """Cycle to equilibrium, failure or the step budget (``workflow.solve``); ``settings`` a
        ``SolveSettings`` and/or its fields as keywords (``ratio=1e-5, max_steps=50_000``)."""
        st = (settings or SolveSettings()).replace(**changes).validated()
        return solve(self, st, check_every=check_every, trace=trace)

    def measure_response(self, watch=()) -> int:
        """Measure and keep the model's response time N_r in steps (``workflow.response``),
        the window of a ``judge="response"`` solve; the model is left as it was."""
        self.response_steps = measure_response(self, tuple(watch))
        # the steps run by measurements (each as many as the N_r it found), for cost reports
        self.measured_steps += self.response_steps
        return self.response_steps

    def search(self):
        """Contact search now (``contact.update.search_contacts``)."""
        new = self.new_contact_material
        new_id = -1 if new is None else self.table.names.index(new)
        before = self.contacts
        self.contacts, changed = search_contacts(self.world(), self.table, new_id,
                                                 self.search_margin, self._moduli(),
                                                 self.options.divide_interfaces)
        energy.bank_dropped(self.energy_bank, before, self.contacts)
        if changed:
            self.update_timestep()

# the options read back as attributes (``model.damping``); ``fixed_dt`` is the option ``dt``
for _name in sorted(set(SolverOptions.__dataclass_fields__) - {"block_E", "block_nu", "dt"}):
    setattr(Model, _name, property(lambda self, n=_name: getattr(self.options, n)))
Model.fixed_dt = property(lambda self: self.options.dt)

