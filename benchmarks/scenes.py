"""Shared scene builders and helpers for the benchmarks (and the tests that import them).

The closed-form scenes of the test suite live here (``block_on_plane``, ``tilt``, ``bonded_pair``
of tests/test_mech_closed_forms.py; ``voronoi_bar``, ``materials``, ``pull``, ``measured_modulus``
of tests/test_mech_specimens.py; ``specimen`` of tests/test_mech_stability.py): the tests import
them from this module (a benchmark never imports a test, docs/architecture.md), so a benchmark
and its test always run the same scene. This module adds what the tests do not need: one
closed-form *measurement* per check (returning the measured value, its closed form and the run
time), plus machine information and the result folder (``outdir``) for the JSON files.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

from dem_core.contact.materials import Material
from dem_core.geometry import GeometrySpec, Voronoi, build_block_system, rectangle
from dem_core.geometry.simple_blocks import from_polygons
from dem_core.model import Model

import outdir

ROOT = Path(__file__).resolve().parents[1]
results_dir = outdir.results_dir     # results/benchmarks/, or benchmarks/results/ (reference)

G = 9.81


# ------------------------------------------------------------------ the closed-form scenes
# (moved unchanged from the test modules named above)
def block_on_plane(friction, width=1.0, height=0.5, **kw):
    """A width x height block on a long fixed base; tilting gravity by theta = inclined plane."""
    bs = from_polygons([[(0, 0), (20, 0), (20, 1), (0, 1)],
                        [(2, 1), (2 + width, 1), (2 + width, 1 + height), (2, 1 + height)]],
                       edge_material="joint:base", groups={"base": [0], "block": [1]})
    m = Model(bs, {"joint:*": Material(kn=1e9, ks=1e9, friction=friction)}, density=2000,
              damping=0.0, **kw)
    m.fix("base")
    return m


def tilt(model, theta_deg):
    th = math.radians(theta_deg)
    model.set_gravity(1.0, direction=(math.sin(th), -math.cos(th)))


def bonded_pair(kn=1e9, ks=1e9, safety=0.5):
    bs = from_polygons([[(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1), (1, 1), (1, 2), (0, 2)]],
                       edge_material="flaw:rock", groups={"base": [0], "top": [1]})
    return Model(bs, {"flaw:*": Material(kn=kn, ks=ks, breakable=False)}, density=2000,
                 damping=0.0, safety=safety)


T = 1.0e6
KN = 1.0e12


def voronoi_bar(length, height, edge=0.005, seed=1, relax=100):
    """A Voronoi bar [0, length] x [0, height] between two rigid platens (single blocks)."""
    p = 2 * edge
    spec = GeometrySpec(regions=[rectangle("rock", 0, 0, length, height),
                                 rectangle("left", -p, 0, 0, height),
                                 rectangle("right", length, 0, length + p, height)],
                        voronoi={"rock": Voronoi(edge_length=edge, seed=seed,
                                                 relax_iterations=relax)})
    return build_block_system(spec)


def materials(ks_ratio):
    """Flaws with T, c = 3T, friction 35; the platen interfaces glued with the same springs."""
    return {"flaw:*": Material(kn=KN, ks=ks_ratio * KN, tensile_strength=T, cohesion=3 * T,
                               friction=35),
            "boundary:*": Material(kn=KN, ks=ks_ratio * KN, breakable=False)}


def pull(bs, length, height, ks_ratio, velocity, max_chunks=400, stop_at=None):
    """Left platen fixed, right platen at constant x velocity; returns (model, strain, stress).

    The strain is the platen displacement over the specimen length.
    """
    m = Model(bs, materials(ks_ratio), density=2500, damping=0.8)
    left, right = bs.groups["left"], bs.groups["right"]
    m.fix(left)
    m.set_velocity(right, vx=velocity, vy=0.0)
    strain, stress = [], []
    for _ in range(max_chunks):
        m.cycle(100)
        # the force on a prescribed block is the contact force on it: minus the applied load
        stress.append(-m.state.force[right, 0].sum() / height)
        strain.append((m.state.pos[right[0], 0] - m.state.pos0[right[0], 0]) / length)
        s = np.array(stress)
        if m.cracks.count[0] and abs(s[-1]) < 0.5 * np.abs(s).max():
            break
        if stop_at is not None and abs(s[-1]) > stop_at:
            break
    return m, np.array(strain), np.array(stress)



def measured_modulus(bs, length, height, ks_ratio):
    """E_2d from the linear part of a compression test (before any damage), Pa."""
    m, strain, stress = pull(bs, length, height, ks_ratio, -2e-3, stop_at=1.5 * T)
    assert m.cracks.count[0] == 0
    s, e = -stress, -strain
    lo, mid = np.searchsorted(s, 0.2 * s[-1]), np.searchsorted(s, 0.6 * s[-1])
    E1 = np.polyfit(e[lo:mid], s[lo:mid], 1)[0]
    E2 = np.polyfit(e[mid:], s[mid:], 1)[0]
    return E1, E2


def specimen(min_fraction=0.15, seed=2, relax=20):
    spec = GeometrySpec(regions=[rectangle("rock", 0, 0, 0.1, 0.05),
                                 rectangle("base", -0.02, -0.02, 0.12, 0.0)],
                        voronoi={"rock": Voronoi(edge_length=0.01, seed=seed, relax_iterations=relax,
                                                 min_edge_fraction=min_fraction,
                                                 min_area_fraction=min_fraction)})
    return build_block_system(spec)


spec_materials, stability_specimen = materials, specimen       # the benchmarks' older names


def quick_or_full_parser(description: str) -> argparse.ArgumentParser:
    """The benchmarks' command line: ``--quick`` (the default) or ``--full``; add more options to
    the returned parser. ``args.full`` tells which; ``args.reference`` where to write
    (``outdir``)."""
    ap = argparse.ArgumentParser(description=description)
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--quick", action="store_true", help="(default)")
    g.add_argument("--full", action="store_true")
    outdir.add_reference_flag(ap)
    return ap


def machine() -> dict:
    """Machine and date stamp for a JSON result."""
    try:
        load = os.getloadavg()
    except OSError:
        load = (float("nan"),) * 3
    cpu = ""
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"node": platform.node(), "cpu": cpu, "cores": os.cpu_count(),
            "platform": platform.platform(), "python": sys.version.split()[0],
            "numpy": np.__version__, "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "load_average_at_start": [round(x, 2) for x in load]}   # (other jobs running?)


def write_json(name: str, payload: dict, reference: bool = False) -> Path:
    """``name``.json in ``results_dir(reference)``."""
    path = results_dir(reference) / f"{name}.json"
    path.write_text(json.dumps(payload, indent=1, default=float))
    return path


# ------------------------------------------------------------------ DEM closed-form measurements
def sliding_block(theta=30.0, friction=20.0, safety=0.5, damping=0.0, steps=6000, kn=None):
    """Relative error of the sliding acceleration against g (sin - cos tan phi).

    The scene of ``test_block_slides_with_coulomb_acceleration``: settled on its base (2000
    steps, damping 0.8, gravity normal to the base), then tilted: 1000 steps to start sliding,
    then the acceleration from the velocity change over ``steps`` steps.
    """
    t0 = time.perf_counter()
    m = block_on_plane(friction, safety=safety)
    if kn is not None:
        m.contacts.kn[:] = kn
        m.contacts.ks[:] = kn
        m.update_timestep()
    m.set_options(damping=0.8)
    tilt(m, 0.0)
    m.cycle(2000)
    m.set_options(damping=damping)
    tilt(m, theta)
    m.cycle(1000)
    t1, v1 = m.time, m.state.vel[1, 0]
    m.cycle(steps)
    a = (m.state.vel[1, 0] - v1) / (m.time - t1)
    th, ph = math.radians(theta), math.radians(friction)
    exact = G * (math.sin(th) - math.cos(th) * math.tan(ph))
    return {"measured": a, "exact": exact, "rel_error": (a - exact) / exact,
            "seconds": time.perf_counter() - t0, "steps": int(m.step), "dt": m.dt}


def oscillation_period(safety=0.5, periods=20):
    """Relative error of the period of a bonded block on a fixed base, undamped.

    The scene of ``test_bonded_block_oscillates_with_spring_mass_period_and_keeps_energy``,
    T = 2 pi sqrt(m / (kn L)); the period from upward zero crossings of the velocity. Also the
    energy drift between the first and the last period.
    """
    t0 = time.perf_counter()
    m = bonded_pair(safety=safety)
    m.fix("base")
    v0 = 0.01
    m.state.vel[1, 1] = v0
    period = 2 * math.pi * math.sqrt(m.props.mass[1] / 1e9)
    n = int(periods * period / m.dt)
    t, vy, energy = np.empty(n), np.empty(n), np.empty(n)
    for i in range(n):
        m.cycle(1)
        t[i], vy[i] = m.time, m.state.vel[1, 1]
        energy[i] = m.kinetic_energy() + m.strain_energy()
    up = np.flatnonzero((vy[:-1] < 0) & (vy[1:] >= 0))
    tc = t[up] - vy[up] * (t[up + 1] - t[up]) / (vy[up + 1] - vy[up])
    measured = float(np.diff(tc).mean())
    per = max(1, int(round(period / m.dt)))
    drift = abs(energy[-per:].mean() - energy[:per].mean()) / energy[:per].mean()
    return {"measured": measured, "exact": period, "rel_error": (measured - period) / period,
            "energy_drift": float(drift), "seconds": time.perf_counter() - t0,
            "steps": int(n), "dt": m.dt}


def brick_bar_tension(cell=0.01, velocity=2e-3, ks_ratio=1.0, safety=0.5, damping=0.8,
                      mass_scaling=False):
    """Relative error of the peak stress of a brick bar in tension against the flaw T.

    The scene of ``test_brick_bar_breaks_at_flaw_tensile_strength`` (0.2 x 0.05 m, end columns
    are the platens), with the brick size, pull velocity and solver controls as arguments.
    """
    from dem_core.model import Model
    from dem_core.geometry.simple_blocks import brick_grid

    t0 = time.perf_counter()
    nx, ny = int(round(0.2 / cell)), int(round(0.05 / cell))
    bs = brick_grid(nx, ny, cell, cell, groups={})
    length, height = (nx - 2) * cell, ny * cell
    m = Model(bs, spec_materials(ks_ratio), density=2500, damping=damping, safety=safety,
              mass_scaling=mass_scaling)
    left, right = bs.groups["left"], bs.groups["right"]
    m.fix(left)
    m.set_velocity(right, vx=velocity, vy=0.0)
    stress = []
    for _ in range(4000):
        m.cycle(100)
        stress.append(-m.state.force[right, 0].sum() / height)
        s = np.array(stress)
        if m.cracks.count[0] and abs(s[-1]) < 0.5 * np.abs(s).max():
            break
    peak = float(np.max(stress))
    return {"measured": peak, "exact": T, "rel_error": (peak - T) / T,
            "seconds": time.perf_counter() - t0, "steps": int(m.step), "dt": m.dt,
            "blocks": bs.n_blocks, "length": length}


_E_CACHE: dict = {}


def cantilever_modulus(edge, seed=4):
    """Assembly E_2d measured by compression of a 0.15 x 0.03 m bar of the same block size
    (the reference of the cantilever check; cached per edge, its cost is reported apart)."""
    key = (edge, seed)
    if key not in _E_CACHE:
        t0 = time.perf_counter()
        _, E = measured_modulus(voronoi_bar(0.15, 0.03, edge=edge, seed=seed), 0.15, 0.03, 1.0)
        _E_CACHE[key] = (E, time.perf_counter() - t0)
    return _E_CACHE[key]


def cantilever(edge=0.005, ratio=1e-5, damping=0.8, safety=0.5, mass_scaling=False,
               max_steps=200_000, seed=3):
    """Relative error of the tip deflection of a Voronoi cantilever under gravity against
    Euler-Bernoulli q L^4 / (8 E I) with E measured (``cantilever_modulus``).

    The scene of ``test_voronoi_cantilever_deflects_like_euler_bernoulli`` (0.3 x 0.03 m).
    ``seconds`` covers building and solving the cantilever, not the E measurement.
    """
    from dem_core.model import Model

    length, height, rho = 0.3, 0.03, 2500.0
    E, e_seconds = cantilever_modulus(edge)
    t0 = time.perf_counter()
    bs = voronoi_bar(length, height, edge=edge, seed=seed)
    m = Model(bs, spec_materials(1.0), density=rho, damping=damping, safety=safety,
              mass_scaling=mass_scaling)
    m.remove("right")
    m.fix("left")
    m.set_gravity(1.0)
    m.add_history_point("tip", (length, 0.5 * height))
    r = m.solve(ratio=ratio, max_steps=max_steps)
    deflection = -m.point_motion("tip")[1]
    exact = rho * G * height * length ** 4 / (8 * E * height ** 3 / 12)
    return {"measured": deflection, "exact": exact, "rel_error": (deflection - exact) / exact,
            "seconds": time.perf_counter() - t0, "steps": int(m.step), "dt": m.dt,
            "verdict": r.verdict, "blocks": bs.n_blocks, "E_2d": E,
            "E_measure_seconds": e_seconds}


# ------------------------------------------------------------------ continuum measurements
def gravity_column(h=1.0, degree=2, n=3.0):
    """Relative error of the top settlement of a laterally confined elastic column under
    gravity against rho g n H^2 / (2 M) (the scene of
    ``test_elastic_column_under_gravity_matches_closed_form``)."""
    from continuum_ref.materials import Elastic
    from continuum_ref.mesh import PolygonRegion, build_mesh
    from continuum_ref.model import ContinuumModel

    W, H, rho = 1.0, 10.0, 2500.0
    mat = Elastic(E=2e9, nu=0.25)
    t0 = time.perf_counter()
    md = build_mesh([PolygonRegion("rock", [(0, 0), (W, 0), (W, H), (0, H)])], h=h,
                    points={"top": (0.5, H)})
    model = ContinuumModel(md, mat, rho, degree=degree)
    model.fix(lambda x: np.isclose(x[1], 0.0), (0, 1))
    model.fix(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], W), (0,))
    result = model.solve_gravity(n)
    lam, Gm = mat.E * mat.nu / ((1 + mat.nu) * (1 - 2 * mat.nu)), mat.E / (2 * (1 + mat.nu))
    exact = rho * G * n * H ** 2 / (2 * (lam + 2 * Gm))
    settlement = float(-model.displacement_at(["top"])[0, 1])
    gamma = rho * G * n
    y = model.cell_average(model._qp_xy)[:, 1]
    stress_err = float(np.max(np.abs(model.stress()[:, 1] + gamma * (H - y))) / (gamma * H))
    return {"measured": settlement, "exact": exact, "rel_error": (settlement - exact) / exact,
            "stress_rel_error": stress_err,
            "seconds": time.perf_counter() - t0, "converged": result.converged,
            "dofs": int(model.V.dofmap.index_map.size_global * 2),
            "newton_iterations": result.newton_iterations}


def gravity_column_stress(**kw):
    """``gravity_column`` with ``rel_error`` = the largest cell-average sigma_yy error over
    gamma H (the settlement is nodally exact even for P1, the stress is not)."""
    r = gravity_column(**kw)
    r["settlement_rel_error"], r["rel_error"] = r["rel_error"], r["stress_rel_error"]
    return r


def strip_footing(h_min=0.03, h_max=0.3, load_steps=10, degree=2):
    """Relative error of the collapse pressure of a smooth strip footing on Tresca soil against
    Prandtl (2 + pi) c (the scene of ``tests/test_continuum_model.py::footing``)."""
    from continuum_ref.materials import MohrCoulomb
    from continuum_ref.mesh import PolygonRegion, build_mesh, refine_near
    from continuum_ref.model import ContinuumModel

    c, half = 1e4, 0.5
    t0 = time.perf_counter()
    md = build_mesh([PolygonRegion("soil", [(0, -2), (3, -2), (3, 0), (half, 0), (0, 0)])],
                    h_max, size_field=refine_near([(half, 0.0)], h_min, h_max, 0.05, 1.0))
    model = ContinuumModel(md, MohrCoulomb(E=1e7, nu=0.3, cohesion=c, friction=0.0), 0.0,
                           degree=degree)
    model.fix(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], 3.0), (0,))
    model.fix(lambda x: np.isclose(x[1], -2.0), (0, 1))
    under = lambda x: np.isclose(x[1], 0.0) & (x[0] <= half + 1e-9)  # noqa: E731
    model.fix(under, (1,), value=(-0.02,))
    iters, ok = 0, True
    for k in range(1, load_steps + 1):
        r = model.solve_load(k / load_steps)
        iters += r.newton_iterations
        ok = ok and r.converged
    q = -model.reaction(under, 1) / half / c
    exact = 2 + math.pi
    return {"measured": q, "exact": exact, "rel_error": (q - exact) / exact,
            "seconds": time.perf_counter() - t0, "converged": ok,
            "dofs": int(model.V.dofmap.index_map.size_global * 2), "newton_iterations": iters}
