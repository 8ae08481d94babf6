"""The Model: a block system with materials, loads and a state, and the driver of the solver.

    model = Model(blocks, {"flaw:*": Material(kn=40e9, ks=20e9, tensile_strength=1.1e6,
                                              cohesion=1.2e6, friction=37)}, density=2400)
    model.fix("bottom")
    model.set_gravity(1.0)
    result = model.solve(ratio=1e-5, max_steps=50_000)   # result.verdict == "equilibrium"

Everything the time step reads is flat arrays (``state.py``, ``contacts.py``); this class only
resolves names (groups, materials), checks input, and calls the numba kernels in chunks of
steps (Python runs between chunks, never inside a step). See docs/mechanics.md.
"""
from __future__ import annotations

import math

import numpy as np

from . import detection, forces, integrate, monitor
from .blocks import BlockSystem
from .contacts import initial_contacts, surface_materials
from .elastic import series_stiffness
from .materials import material_table
from .state import FIX_ROT, FIX_X, FIX_Y, BlockProps, BlockState

__all__ = ["Model", "ModelUnstable"]

STANDARD_GRAVITY = 9.81


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
        Time step = safety x critical step (``integrate.frequency_bound``).
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
        Threads for the contact forces (1: the serial kernel; more: ``dem_core.parallel``,
        bit-for-bit the same results). At most numba's thread count (the cores).
    kinetic_damping : int
        Dynamic relaxation: every ``kinetic_damping`` steps (0: off) compare the kinetic energy
        with the last check and zero all free velocities when it has fallen (a kinetic-energy
        peak, ``integrate``). For quasi-static runs of slender structures (toppling columns),
        whose lowest mode local damping turns into a creep lasting many of its periods; 100
        steps suits models whose slowest period is thousands of steps.
    """

    def __init__(self, blocks: BlockSystem, materials: dict, density, block_E=None,
                 block_nu=0.25, unbreakable=None, damping=0.8, safety=0.5, mass_scaling=False,
                 dt=None, search_margin=None, new_contact_material=None, history_every=100,
                 threads=1, kinetic_damping=0):
        if not isinstance(blocks, BlockSystem):
            raise ValueError(f"blocks must be a BlockSystem, got {type(blocks).__name__}")
        if not (0.0 <= damping < 1.0):
            raise ValueError(f"damping must be in [0, 1), got {damping!r}")
        if not (0.0 < safety <= 1.0):
            raise ValueError(f"safety must be in (0, 1], got {safety!r}")
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
        self.props = BlockProps.from_block_system(blocks, density)
        self.state = BlockState.at_rest(blocks.centroid)
        nb = blocks.n_blocks
        self.block_E = self._per_block(block_E, np.inf, "block_E", lower=0.0)
        self.block_nu = self._per_block(block_nu, 0.25, "block_nu", lower=-1.0, upper=0.5)
        self.damping = float(damping)
        if not (isinstance(kinetic_damping, (int, np.integer)) and kinetic_damping >= 0):
            raise ValueError(f"kinetic_damping must be a step interval >= 0 (0: off), got "
                             f"{kinetic_damping!r}")
        self.kinetic_damping = int(kinetic_damping)
        self.ke_last = np.zeros(3)     # integrate.run_steps: kinetic-damping state
        self.safety = float(safety)
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
        self.gravity = np.zeros(2)
        self.time = 0.0
        self.step = 0
        self.history = monitor.History(every=int(history_every))
        self.points = {}                       # name -> (block, local point (2,))
        self.servo_groups = []                 # (blocks, params row)
        self._rot = np.zeros((nb, 2))
        integrate.update_rotation(self.state.theta, self._rot)
        self.contacts = detection.sort_for_locality(initial_contacts(blocks))
        self.props.surface_material = surface_materials(self.contacts, len(blocks.vertices))
        self._set_contact_stiffness(0, self.contacts.n)
        nbonded = self.contacts.n
        self.cracks = np.zeros((nbonded + 16, 7))
        self.crack_count = np.zeros(1, np.int64)
        self.dt = None
        self._update_timestep()
        self.search()           # touching blocks that share no edge get (unbonded) contacts

    # ----------------------------------------------------------------- input helpers
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
    def _set_contact_stiffness(self, start, stop):
        """Effective kn, ks of contacts [start, stop): material in series with the blocks."""
        c, s = self.contacts, slice(start, stop)
        if stop <= start:
            return
        a, b, m = c.block_a[s], c.block_b[s], c.material[s]
        pos = self.state.pos
        xa = c.position(pos, self.state.theta)[start:stop]
        th = self.state.theta[b]
        nb = c.normal_b[s]
        n = np.column_stack([np.cos(th) * nb[:, 0] - np.sin(th) * nb[:, 1],
                             np.sin(th) * nb[:, 0] + np.cos(th) * nb[:, 1]])
        h_a = np.abs(((xa - pos[a]) * n).sum(axis=1))
        h_b = np.abs(((xa - pos[b]) * n).sum(axis=1))
        c.kn[s], c.ks[s] = series_stiffness(self.table.kn[m], self.table.ks[m], h_a, h_b,
                                            self.block_E[a], self.block_nu[a],
                                            self.block_E[b], self.block_nu[b])

    def _update_timestep(self):
        """Automatic step (and inertial masses with mass scaling) from the current contacts."""
        p, c = self.props, self.contacts
        w2 = integrate.frequency_bound(c.n, c.block_a, c.block_b, c.point_a, c.length, c.kn,
                                       c.ks, self.state.pos, self._rot, p.mass, p.inertia)
        # a block without contacts may meet one: bound it by a contact of its own size made of
        # the new-contact material
        if self.new_contact_material is not None:
            mid = self.table.names.index(self.new_contact_material)
            kk = (self.table.kn[mid] + self.table.ks[mid]) * p.radius
            w2 = np.maximum(w2, 2.0 * (kk / p.mass + kk * p.radius ** 2 / p.inertia))
        moving = (p.active > 0) & (p.fixity != (FIX_X | FIX_Y | FIX_ROT)) & (w2 > 0)
        scale = np.ones(self.n_blocks)
        if self.mass_scaling and moving.any():
            target = float(np.median(w2[moving]))
            scale = np.maximum(1.0, w2 / target)
            w2 = w2 / scale
        p.inv_mass = 1.0 / (p.mass * scale)
        p.inv_inertia = 1.0 / (p.inertia * scale)
        w2max = float(w2[moving].max()) if moving.any() else 0.0
        self.critical_dt = 2.0 / math.sqrt(w2max) if w2max > 0 else math.inf
        if self.fixed_dt is not None:
            self.dt = float(self.fixed_dt)
        elif math.isfinite(self.critical_dt):
            self.dt = self.safety * self.critical_dt
        elif self.dt is None:
            self.dt = None       # no contacts yet: cycle() will ask for a dt

    # ----------------------------------------------------------------- loading
    def set_gravity(self, g_level=1.0, g=STANDARD_GRAVITY, direction=(0.0, -1.0)):
        """Gravity of ``g_level`` x ``g`` (m/s^2) along ``direction`` (centrifuge: raise g_level)."""
        d = np.asarray(direction, dtype=np.float64)
        if not (np.all(np.isfinite(d)) and np.hypot(*d) > 0 and math.isfinite(g_level)
                and g_level >= 0):
            raise ValueError(f"bad gravity: g_level={g_level!r}, direction={direction!r}")
        self.gravity = g_level * g * d / np.hypot(*d)

    def fix(self, group, x=True, y=True, rotation=True):
        """Hold the chosen velocity components of a group at zero (a roller: ``x=False``)."""
        self.set_velocity(group, 0.0 if x else None, 0.0 if y else None,
                          0.0 if rotation else None)

    def free(self, group):
        """Release every prescribed velocity component of a group."""
        idx = self.group(group)
        self.props.fixity[idx] = 0
        self._update_timestep()

    def set_velocity(self, group, vx=None, vy=None, omega=0.0):
        """Prescribe velocities (m/s, rad/s) of a group; None leaves that component free."""
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
        self._update_timestep()

    def apply_load(self, group, fx=0.0, fy=0.0, moment=0.0):
        """A constant total force (N/m) on a group, shared by mass; a moment (N m/m) per block."""
        idx = self.group(group)
        if not all(math.isfinite(v) for v in (fx, fy, moment)):
            raise ValueError(f"load must be finite, got {(fx, fy, moment)!r}")
        w = self.props.mass[idx] / self.props.mass[idx].sum()
        self.props.load[idx, 0] = fx * w
        self.props.load[idx, 1] = fy * w
        self.props.load[idx, 2] = moment

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

        ``name`` is a key of the materials mapping (exact or pattern). Broken contacts stay
        broken; stiffness changes apply to every contact of that material.
        """
        if name not in self.materials:
            raise ValueError(f"no material {name!r}; materials are {sorted(self.materials)}")
        self.materials[name] = self.materials[name].with_strength(**changes)
        self.table = material_table(self.table.names, self.materials, self.unbreakable)
        self._set_contact_stiffness(0, self.contacts.n)
        self._update_timestep()

    def remove(self, group):
        """Excavate: remove a group's blocks and every contact they have."""
        idx = self.group(group)
        p = self.props
        p.active[idx] = 0
        p.fixity[idx] = FIX_X | FIX_Y | FIX_ROT
        p.velocity_bc[idx] = 0.0
        self.state.vel[idx] = 0.0
        self.state.omega[idx] = 0.0
        c = self.contacts
        keep = (p.active[c.block_a[:c.n]] > 0) & (p.active[c.block_b[:c.n]] > 0)
        self.contacts = detection.compact(c, np.flatnonzero(keep))
        self._update_timestep()

    def save(self, path):
        """Write the whole model to ``path`` (.npz); ``Model.load`` resumes it bit-for-bit."""
        from .io import save_model
        save_model(self, path)

    @staticmethod
    def load(path) -> "Model":
        from .io import load_model
        return load_model(path)

    # ----------------------------------------------------------------- monitors
    def add_history_point(self, name, xy):
        """Record displacement and velocity of the body point at ``xy`` (m) as ``name``."""
        xy = np.asarray(xy, dtype=np.float64)
        b = detection.block_containing(self.props, self.state.pos, self._rot, xy)
        local = xy - self.state.pos[b]
        c, s = self._rot[b]
        self.points[name] = (b, np.array([c * local[0] + s * local[1],
                                          -s * local[0] + c * local[1]]), xy.copy())

    def point_motion(self, name):
        """(ux, uy, vx, vy) of a history point now, m and m/s."""
        b, r, x0 = self.points[name]
        c, s = self._rot[b]
        x = self.state.pos[b] + np.array([c * r[0] - s * r[1], s * r[0] + c * r[1]])
        w = self.state.omega[b]
        v = self.state.vel[b] + w * np.array([-(x[1] - self.state.pos[b, 1]),
                                              x[0] - self.state.pos[b, 0]])
        return x[0] - x0[0], x[1] - x0[1], v[0], v[1]

    def unbalanced_ratio(self) -> float:
        p, c = self.props, self.contacts
        return monitor.unbalanced_ratio(self.state.force, p.mass, self.gravity, p.load,
                                        p.fixity, p.active, c.n, c.block_a, c.block_b,
                                        c.length, c.sn, c.ts)

    def kinetic_energy(self) -> float:
        p = self.props
        return monitor.kinetic_energy(self.state.vel, self.state.omega, p.mass, p.inertia,
                                      p.active)

    def strain_energy(self) -> float:
        c = self.contacts
        return monitor.strain_energy(c.n, c.length, c.kn, c.ks, c.sn, c.ts)

    def gravity_energy(self) -> float:
        """Potential of gravity relative to the initial positions, J/m."""
        a = self.props.active > 0
        du = self.state.pos[a] - self.state.pos0[a]
        return float(-(self.props.mass[a] * (du @ self.gravity)).sum())

    def displacement(self) -> np.ndarray:
        """(nb, 2) centroid displacement from the start, m."""
        return self.state.pos - self.state.pos0

    def crack_log(self) -> dict:
        """Every failure so far: time (s), x, y (m), mode (1 tension, 2 shear), blocks, material."""
        n = min(int(self.crack_count[0]), self.cracks.shape[0])
        r = self.cracks[:n]
        return {"time": r[:, 0].copy(), "x": r[:, 1].copy(), "y": r[:, 2].copy(),
                "mode": r[:, 3].astype(np.int8), "block_a": r[:, 4].astype(np.int64),
                "block_b": r[:, 5].astype(np.int64),
                "material": [self.table.names[int(m)] for m in r[:, 6]]}

    def crack_counts(self) -> dict:
        mode = self.cracks[:int(self.crack_count[0]), 3]
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
    def _servo_arrays(self):
        if not self.servo_groups:
            return forces.no_servo()
        offs = np.concatenate([[0], np.cumsum([len(g) for g, _ in self.servo_groups])])
        blocks = np.concatenate([g for g, _ in self.servo_groups]).astype(np.int64)
        return offs.astype(np.int64), blocks, np.array([p for _, p in self.servo_groups])

    def _parallel_arrays(self):
        """Scratch and the block -> contact table for the threaded kernel (empty: serial)."""
        if self.threads <= 1:
            return ()
        import numba

        from .parallel import contact_table
        numba.set_num_threads(self.threads)
        c = self.contacts
        offsets, entries = contact_table(c.n, c.block_a, c.block_b, self.n_blocks)
        return np.empty((c.n, 4)), np.empty(c.n, np.int64), offsets, entries

    def _run(self, n):
        p, s, c = self.props, self.state, self.contacts
        so, sb, sp = self._servo_arrays()
        flags = np.array([np.any(self.gravity != 0), np.any(p.load != 0), len(sp) > 0,
                          self.search_enabled, self.kinetic_damping], dtype=np.int64)
        steps, self.time, status, bad = integrate.run_steps(
            n, self.time, self.dt, self.damping, 0.5 * self.search_margin, self.gravity, flags,
            s.pos, s.theta, s.vel, s.omega, s.force, self._rot, s.pos_search, s.theta_search,
            p.mass, p.inv_mass, p.inv_inertia, p.radius, p.fixity, p.velocity_bc, p.load,
            p.active, c.n, c.block_a, c.block_b, c.point_a, c.point_b, c.normal_b, c.length,
            c.kn, c.ks, c.material, c.sn, c.ts, c.un, c.us, c.up, c.broken, c.slipping,
            self.table.strength_array(), self.cracks, self.crack_count, so, sb, sp,
            self.ke_last, *self._parallel_arrays())
        self.step += steps
        if status == integrate.UNSTABLE:
            raise ModelUnstable(self._diagnose(bad))
        if status == integrate.NEED_SEARCH:
            self.search()
        return steps

    def cycle(self, n: int):
        """Advance ``n`` steps (histories recorded every ``history.every`` steps)."""
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
              creep=None, trace=None):
        """Cycle until the unbalanced ratio <= ``ratio`` or ``max_steps``; returns a SolveResult.

        ``failure_displacement`` (m): stop as "failed" once a block has moved this far during
        the solve. ``creep`` (m, default 1e-3 of the median block radius): displacement
        increments below this do not count as movement in the end-of-run test
        (``monitor.verdict``). ``trace``: optional (steps, displacements) lists, each starting
        with 0, that the checks are appended to (still readable after a ``ModelUnstable``).
        """
        if not (ratio > 0):
            raise ValueError(f"ratio must be > 0, got {ratio!r}")
        check = int(check_every or max(self.history.every, 100))
        creep = 1e-3 * float(np.median(self.props.radius)) if creep is None else creep
        start = self.state.pos.copy()
        act = self.props.active > 0
        steps, disp = trace if trace is not None else ([0], [0.0])
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
        v, why = monitor.verdict(steps, disp, creep)
        return monitor.SolveResult(v, done, r, max(disp), why)

    def search(self):
        """Contact search now: keep surviving contacts (with history), add new ones."""
        old_n = self.contacts.n
        self.contacts, n_new = detection.update_contacts(self, self.search_margin)
        if n_new:
            self._set_contact_stiffness(self.contacts.n - n_new, self.contacts.n)
            self.contacts = detection.sort_for_locality(self.contacts)
        self.state.pos_search[:] = self.state.pos
        self.state.theta_search[:] = self.state.theta
        if n_new or self.contacts.n != old_n:
            self._update_timestep()

    def _diagnose(self, b) -> str:
        p, c = self.props, self.contacts
        mine = np.flatnonzero((c.block_a[:c.n] == b) | (c.block_b[:c.n] == b))
        kmax = float(c.kn[mine].max()) if mine.size else 0.0
        area = float(self.blocks.area[b])
        med = float(np.median(self.blocks.area))
        cause = []
        if area < 1e-3 * med:
            cause.append(f"a sliver (area {area:.3g} m^2 vs median {med:.3g}): merge it or use "
                         "mass_scaling=True")
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
