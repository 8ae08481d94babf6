"""Three other shapes of the serial contact pass against the model's (issue 29 item 2).

    .venv/bin/python benchmarks/trials/contact_pass_trials.py [--blocks 10000 100000] [--rounds 7]

The model's serial step runs about 2.6 times the memory-bandwidth bound at 1e5 blocks where the
goal is 2 (docs/performance.md, "The machine limit"). A loop that streams the same bytes with no
block data reaches the bound, so the time is in the gathers of block data and the arithmetic
between them. These trials test three ways to cut that, each a kernel written here for the
bonded specimen of ``throughput.py`` (rigid blocks, sharp corners, no edge elements, the elastic
branch of the law), checked bit for bit against the model's kernel before it is timed:

- ``model``: ``dem_core.contact.forces.add_contact_forces``, the step's contact pass.
- ``one_loop``: the same arithmetic in one loop that has none of the model's other paths
  (rounded corners, deformable blocks, edge elements, chunk ownership, the crack log): what
  the model's generality costs.
- ``two_pass``: a law pass with no branch around a memory access and four flat outputs (force,
  point), compiled with numba's ``noalias`` flag (numba's parfor lowering sets it on loops it
  has proven free of aliases; here it is set by hand, ``_noalias_compiles``) so that LLVM can
  vectorise it (it does: AVX2, four lanes, the block data by gather instructions); then a
  scatter pass adds the forces to the blocks. ``law_pass`` is the first pass alone.
- ``record``: ``one_loop`` on a block's pose (x, y, cos, sin and the half-angle pair) kept in
  one 64-byte row (its three arrays are views of the rows), so a block's gathers touch one
  cache line, not three.

All are timed in alternating rounds of about 2e7 contact updates, on one thread; ns per
contact, best and median of the rounds. One JSON line a size to stdout, and all in
results/benchmarks/contact_pass_trials.json and .png (the committed record:
benchmarks/results/contact_pass_trials.json, .png). The kernels are measurements, not the model's:
only the elastic branch is written (no failure, slip bookkeeping or re-anchoring).
"""
from __future__ import annotations

import argparse
import contextlib
import json
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit

HERE = Path(__file__).resolve().parent
BENCHMARKS = HERE.parent                  # a trial uses the benchmarks' modules (trials/README.md)
sys.path.insert(0, str(BENCHMARKS))
sys.path.insert(0, str(BENCHMARKS.parent))

import outdir  # noqa: E402


@contextlib.contextmanager
def _noalias_compiles():
    """Functions compiled inside mark their array arguments ``noalias`` (numba's compiler flag
    of that name, which its public decorator does not expose)."""
    from numba.core.cpu import CPUTargetOptions
    original = CPUTargetOptions.finalize

    def finalize(self, flags, options):
        original(self, flags, options)
        flags.noalias = True
    CPUTargetOptions.finalize = finalize
    try:
        yield
    finally:
        CPUTargetOptions.finalize = original


@njit(inline="always")
def _law(k, xa, ya, xb, yb, nx, ny, cs, strength):
    """The elastic-or-limit law of ``dem_core.contact.law.coulomb_law`` by selects (glued, tension
    cut-off, Coulomb limit), the state written back; returns (fx, fy, px, py), the force on B
    and its point (``dem_core.contact.forces.contact_update``)."""
    un, us, sne, ts, sn, kn, ks, material, broken, length, anchor = cs
    u_n = (xb - xa) * nx + (yb - ya) * ny
    u_s = (yb - ya) * nx - (xb - xa) * ny
    m = material[k]
    s_e = sne[k] - kn[k] * (u_n - un[k])
    trial = ts[k] - ks[k] * (u_s - us[k])
    residual = broken[k] != 0
    T = strength[m, 3] if residual else strength[m, 0]
    c = strength[m, 4] if residual else strength[m, 1]
    tan_phi = strength[m, 5] if residual else strength[m, 2]
    tau = c + s_e * tan_phi
    tau = tau if tau > 0.0 else 0.0
    glued = strength[m, 6] == 0.0
    opened = s_e < -T and not glued
    slip = abs(trial) > tau and not glued and not opened
    s_n = 0.0 if opened else s_e
    t_s = 0.0 if opened else ((tau if trial > 0.0 else -tau) if slip else trial)
    sn[k], ts[k], sne[k], un[k], us[k] = s_n, t_s, s_e, u_n, u_s
    an = anchor[k]
    px = xa if an == 0 else (xb if an == 1 else 0.5 * (xa + xb))
    py = ya if an == 0 else (yb if an == 1 else 0.5 * (ya + yb))
    L = length[k]
    return L * (s_n * nx - t_s * ny), L * (s_n * ny + t_s * nx), px, py


@njit(inline="always")
def _points(k, geo, x, y, cosine, sine, half_cos, half_sin, a, b):
    """World points of A and B and the contact normal (``kinematics``), the block pose given
    as scalars read by the caller."""
    point_a, point_b, normal_b, face = geo
    rx, ry = point_b[k, 0], point_b[k, 1]
    xb, yb = x[1] + (cosine[1] * rx - sine[1] * ry), y[1] + (sine[1] * rx + cosine[1] * ry)
    rx, ry = point_a[k, 0], point_a[k, 1]
    xa, ya = x[0] + (cosine[0] * rx - sine[0] * ry), y[0] + (sine[0] * rx + cosine[0] * ry)
    nbx, nby = normal_b[k, 0], normal_b[k, 1]
    if face[k] == 0:
        nx, ny = cosine[1] * nbx - sine[1] * nby, sine[1] * nbx + cosine[1] * nby
    else:
        x1 = half_cos[1] * nbx - half_sin[1] * nby
        y1 = half_sin[1] * nbx + half_cos[1] * nby
        nx, ny = half_cos[0] * x1 - half_sin[0] * y1, half_sin[0] * x1 + half_cos[0] * y1
    return xa, ya, xb, yb, nx, ny


@njit(inline="always")
def _add(f, pos, a, b, fx, fy, px, py):
    f[b, 0] += fx
    f[b, 1] += fy
    f[b, 2] += (px - pos[b, 0]) * fy - (py - pos[b, 1]) * fx
    f[a, 0] -= fx
    f[a, 1] -= fy
    f[a, 2] -= (px - pos[a, 0]) * fy - (py - pos[a, 1]) * fx


@njit
def one_loop(reps, n, block_a, block_b, geo, cs, strength, pos, rot, rot_half, f):
    for _ in range(reps):
        f[:] = 0.0
        for k in range(n):
            a, b = block_a[k], block_b[k]
            xa, ya, xb, yb, nx, ny = _points(
                k, geo, (pos[a, 0], pos[b, 0]), (pos[a, 1], pos[b, 1]),
                (rot[a, 0], rot[b, 0]), (rot[a, 1], rot[b, 1]),
                (rot_half[a, 0], rot_half[b, 0]), (rot_half[a, 1], rot_half[b, 1]), a, b)
            fx, fy, px, py = _law(k, xa, ya, xb, yb, nx, ny, cs, strength)
            _add(f, pos, a, b, fx, fy, px, py)


def _law_pass_source():
    """The first pass of ``two_pass`` (compiled in ``_noalias_compiles``): one flat argument
    per array, since a tuple of arrays is one aggregate whose members LLVM cannot tell apart."""
    @njit
    def law_pass(n, block_a, block_b, point_a, point_b, normal_b, face, un, us, sne, ts, sn,
                 kn, ks, material, broken, length, anchor, strength, pos, rot, rot_half,
                 out_fx, out_fy, out_px, out_py):
        for k in range(n):
            a, b = block_a[k], block_b[k]
            xa, ya, xb, yb, nx, ny = _points(
                k, (point_a, point_b, normal_b, face), (pos[a, 0], pos[b, 0]),
                (pos[a, 1], pos[b, 1]), (rot[a, 0], rot[b, 0]), (rot[a, 1], rot[b, 1]),
                (rot_half[a, 0], rot_half[b, 0]), (rot_half[a, 1], rot_half[b, 1]), a, b)
            fx, fy, px, py = _law(k, xa, ya, xb, yb, nx, ny,
                                  (un, us, sne, ts, sn, kn, ks, material, broken, length,
                                   anchor), strength)
            out_fx[k], out_fy[k], out_px[k], out_py[k] = fx, fy, px, py
    return law_pass


@njit
def _scatter(n, block_a, block_b, out_fx, out_fy, out_px, out_py, pos, f):
    for k in range(n):
        _add(f, pos, block_a[k], block_b[k], out_fx[k], out_fy[k], out_px[k], out_py[k])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, nargs="+", default=[10_000, 100_000])
    ap.add_argument("--rounds", type=int, default=7)
    a = ap.parse_args(argv)
    from performance import BYTES_PER_CONTACT, bandwidth
    rows = [trial(n_blocks, a.rounds) for n_blocks in a.blocks]
    copy = max(bandwidth()["copy_GB_s"] for _ in range(3))
    out = {"copy_GB_s": round(copy, 2), "bytes_per_contact_update": BYTES_PER_CONTACT,
           "bound_ns_per_update": round(BYTES_PER_CONTACT / copy, 2), "sizes": rows}
    print(json.dumps({k: v for k, v in out.items() if k != "sizes"}), flush=True)
    (outdir.results_dir() / "contact_pass_trials.json").write_text(json.dumps(out, indent=1) + "\n")
    figure(out, outdir.results_dir() / "contact_pass_trials.png")


LABELS = {"model": "the model's\ncontact pass", "one_loop": "one loop,\nno other paths",
          "record": "one row per\nblock's pose", "two_pass": "vectorised law\n+ scatter pass",
          "law_pass": "the vectorised\nlaw pass alone"}


def figure(out, path):
    """Bars: each trial's best ns per contact at each size (the median as a tick above), with
    the bandwidth bound and the goal (2x the bound) of the same run."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 4.5))
    names = list(LABELS)
    width = 0.8 / len(out["sizes"])
    for i, row in enumerate(out["sizes"]):
        x = np.arange(len(names)) + (i - 0.5 * (len(out["sizes"]) - 1)) * width
        ax.bar(x, [row["ns_per_contact_best"][n] for n in names], width,
               label=f"{row['blocks']:,} blocks (best of {row['rounds']} rounds)")
        ax.plot(x, [row["ns_per_contact_median"][n] for n in names], "_", color="k", ms=12)
    bound = out["bound_ns_per_update"]
    ax.axhline(bound, color="tab:green", lw=1,
               label=f"bandwidth bound, {bound:.1f} ns ({out['bytes_per_contact_update']} B at "
                     f"{out['copy_GB_s']:.1f} GB/s, this run's copy)")
    ax.axhline(2 * bound, color="tab:red", lw=1, ls="--",
               label=f"goal for the whole step: 2x the bound, {2 * bound:.1f} ns")
    ax.set_xticks(np.arange(len(names)), [LABELS[n] for n in names], fontsize=8)
    ax.set_ylabel("ns per contact update (tick: median)")
    ax.set_title("Other shapes of the serial contact pass, bonded specimen, one thread",
                 fontsize=9)
    ax.legend(fontsize=8, loc="upper left", ncol=2)
    ax.set_ylim(0, 1.45 * max(max(r["ns_per_contact_median"].values()) for r in out["sizes"]))
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def trial(n_blocks, rounds):
    """One specimen of about ``n_blocks`` blocks: the trials' bit-for-bit check and times."""
    from dem_core.contact.materials import Material
    from dem_core.model import Model
    from scenes import machine
    from throughput import specimen
    from two_threads import _loops

    flaw = Material(kn=40e9, ks=20e9, tensile_strength=1.1e6, cohesion=1.2e6, friction=37)
    m = Model(specimen(n_blocks), {"flaw:*": flaw, "boundary:*": flaw}, density=1700,
              history_every=10**9)
    m.fix("base")
    m.set_gravity(50.0)
    m.cycle(200)                              # settle into an elastic, bonded state
    c, s, strength = m.contacts, m.state, m.table.strength_array()
    n = int(c.count[0])
    state_names = ("un", "us", "sn_elastic", "ts", "sn")
    saved = {k: getattr(c, k).copy() for k in state_names}
    geo = (c.point_a, c.point_b, c.normal_b, c.face)
    cs = (c.un, c.us, c.sn_elastic, c.ts, c.sn, c.kn, c.ks, c.material, c.broken, c.length,
          c.anchor)
    pose = np.zeros((m.n_blocks, 8))
    pose[:, 0:2], pose[:, 2:4], pose[:, 4:6] = s.pos, s.rot, s.rot_half
    out = [np.zeros(n) for _ in range(4)]
    with _noalias_compiles():
        law_pass = _law_pass_source()
        flat = (n, c.block_a, c.block_b, *geo, *cs, strength, s.pos, s.rot, s.rot_half, *out)
        law_pass(*flat)                        # compiled here, with the flag
    vectorised = "vector.body" in law_pass.inspect_llvm(law_pass.signatures[0])

    model = _loops()[0]                          # the model's serial contact pass

    @njit
    def two_pass(reps, flat_tail, f):
        for _ in range(reps):
            f[:] = 0.0
            law_pass(*flat_tail)
            _scatter(flat_tail[0], flat_tail[1], flat_tail[2], flat_tail[-4], flat_tail[-3],
                     flat_tail[-2], flat_tail[-1], flat_tail[-7], f)

    @njit
    def law_only(reps, flat_tail):
        for _ in range(reps):
            law_pass(*flat_tail)

    f = np.zeros_like(s.force)
    trials = {
        "model": (model, (c, strength, s, m.cracks, m.corners, m.zone_state), s.force),
        "one_loop": (one_loop, (n, c.block_a, c.block_b, geo, cs, strength, s.pos, s.rot,
                                s.rot_half, f), f),
        "two_pass": (two_pass, (flat, f), f),
        # one_loop on views of the rows: x, y, cos, sin, half-angle cos, sin in one line
        "record": (one_loop, (n, c.block_a, c.block_b, geo, cs, strength, pose[:, 0:2],
                              pose[:, 2:4], pose[:, 4:6], f), f),
        "law_pass": (law_only, (flat,), None),
    }
    same, reference = {}, None
    for name, (fn, args, force) in trials.items():   # one call each from the same state
        fn(1, *args)
        got = {k: getattr(c, k)[:n].copy() for k in state_names}
        if force is not None:
            got["force"] = force.copy()
        if reference is None:
            reference = got
        same[name] = all(np.array_equal(v, reference[k]) for k, v in got.items())
        for k, v in saved.items():
            getattr(c, k)[:] = v
    reps = max(1, int(2e7 / n))
    times = {name: [] for name in trials}
    for _ in range(rounds):
        for name, (fn, args, _force) in trials.items():
            t0 = time.perf_counter()
            fn(reps, *args)
            times[name].append(1e9 * (time.perf_counter() - t0) / (reps * n))
    row = {"blocks": m.n_blocks, "contacts": n, "rounds": rounds,
           "law_pass_vectorised": vectorised, "bit_for_bit_with_model": same,
           "ns_per_contact_best": {k: round(min(v), 2) for k, v in times.items()},
           "ns_per_contact_median": {k: round(float(np.median(v)), 2)
                                     for k, v in times.items()},
           "machine": machine()}
    print(json.dumps(row), flush=True)
    return row


if __name__ == "__main__":
    main()
