"""DEM throughput and scaling, a profile of the time step, the machine limit, and the continuum's
time per Newton iteration against dofs.

    .venv/bin/python benchmarks/performance.py [--quick | --full]
    .venv/bin/python benchmarks/performance.py --limit 100000 [--rounds 3]   # the limit alone
    .venv/bin/python benchmarks/performance.py --streams   # the stream loop against its size

- Scaling: ``throughput.run`` (bonded Voronoi square on a fixed base at 50 g) for 1e3..1e4
  (quick) or 1e3..1e5 (full) blocks, with 1 thread (the serial kernel) and 2 threads (the
  threaded kernel of ``dem_core.step.threads.parallel``, ``Model(threads=2)``); contact updates per second
  per core = updates / s / threads, and the speed-up of 2 threads over 1 at each size.
- Profile: the parts of one step timed separately on one specimen by calling the same numba
  kernels the step calls (``forces.add_contact_forces``, ``step.advance`` (which also turns
  each block's ``rot``), the zeroing of the force array, ``components.add_gravity``).
- Machine limit: memory bandwidth from numpy copies (``dst[:] = src``, 2 x 200 MB, counted as
  read + write) and a triad; the bytes streamed and the flops per contact update counted from the
  kernel source (see ``BYTES_PER_CONTACT``); the bandwidth-bound time per contact update is
  bytes / bandwidth. ``--limit`` also times ``_stream``: the same bytes in the same 18 arrays
  through a numba loop of the contact pass's shape, without its arithmetic and block gathers
  (what memory gives such a loop on this machine).
- Continuum: elastic and Mohr-Coulomb centrifuge slope (``continuum_scaling.slope_case``),
  seconds per Newton iteration against dofs.
Writes results/benchmarks/performance.json and .png, ``--streams`` stream_footprint.json and
.png there (``--reference``: benchmarks/results/).
"""
from __future__ import annotations

import time

import numpy as np
from numba import njit

import scenes
import throughput

# Streamed per contact and step by add_contact_forces on the elastic path of a rigid-block model
# (dtypes of dem_core.contact.contacts; recounted 2026-11-26 for the incremental law's layout): read
# block_a, block_b (int32 4+4), point_a, point_b, normal_b (3 x 16), face, anchor, broken (int8
# 3 x 1), length, kn, ks (3 x 8), material (4), sn_elastic, ts, un, us (4 x 8) = 119 B; written
# sn, ts, sn_elastic, un, us (5 x 8) + slipping (1) = 41 B, of which sn and slipping (9 B) are
# lines not read before (write-allocate: read once more) -> 119 + 41 + 9 = 169 B. (up is read
# and written only when a contact slips or breaks; partner only with edge elements.)
# The block data (pos, rot, rot_half gathered; f read-modify-written) stay in cache when
# contacts are ordered by block (sort_for_locality) and are not counted.
BYTES_PER_CONTACT = 169
# Arithmetic per contact (from the source; mul/add/compare, no division or sqrt on the elastic
# path): world points and gap 2 x 8 + 2, normal 6, u_n, u_s 6, law ~ 10, forces 6, moments 2 x 5,
# force scatter 6 adds -> about 60 flops.
FLOPS_PER_CONTACT = 60


def bandwidth(mb=200, reps=5):
    n = mb * 2 ** 20 // 8
    src = np.random.default_rng(0).random(n)
    dst = np.empty_like(src)
    c = np.empty_like(src)
    best_copy = best_triad = np.inf
    for _ in range(reps):
        t0 = time.perf_counter()
        dst[:] = src
        best_copy = min(best_copy, time.perf_counter() - t0)
        t0 = time.perf_counter()
        np.multiply(src, 2.0, out=c)
        np.add(c, dst, out=c)          # two passes: read 2, write 1 then read 2, write 1
        best_triad = min(best_triad, time.perf_counter() - t0)
    byte = 8 * n
    # copy: read + write (+ write-allocate read, not counted: the conservative, STREAM-like figure)
    return {"array_MB": mb, "copy_GB_s": 2 * byte / best_copy / 1e9,
            "two_pass_triad_GB_s": 6 * byte / best_triad / 1e9}


def contact_streams(n):
    """Arrays with the contact pass's streamed layout (``BYTES_PER_CONTACT``), ``n`` contacts:
    the 14 read-only ones, the 4 read and rewritten, and the 2 written only."""
    rng = np.random.default_rng(1)
    f8 = lambda *shape: rng.random(shape)                                 # noqa: E731
    i4 = lambda: rng.integers(0, 1000, n).astype(np.int32)               # noqa: E731
    i1 = lambda: np.zeros(n, np.int8)                                    # noqa: E731
    read = (i4(), i4(), f8(n, 2), f8(n, 2), f8(n, 2), i1(), i1(), i1(), f8(n), f8(n), f8(n),
            i4())
    rewrite = (f8(n), f8(n), f8(n), f8(n))
    write = (np.empty(n), np.empty(n, np.int8))
    return read, rewrite, write


@njit(cache=True)
def _stream(read, rewrite, write):
    """One pass over ``contact_streams``: every byte the contact pass streams is read or written
    once, in the same arrays and order, with a few operations between (no gathers of block
    data). Its time is what memory gives a loop of this shape: the step's own bound."""
    a, b, pa, pb, nb, face, anchor, broken, length, kn, ks, mat = read
    sne, ts, un, us = rewrite
    sn, slipping = write
    for k in range(a.shape[0]):
        x = (pa[k, 0] - pb[k, 0]) * nb[k, 0] + (pa[k, 1] - pb[k, 1]) * nb[k, 1]
        x += length[k] * (kn[k] + ks[k]) + a[k] + b[k] + mat[k]
        x += face[k] + anchor[k] + broken[k]
        sn[k] = sne[k] + x
        sne[k] = sn[k] * 0.5
        ts[k] += x
        un[k] -= x
        us[k] += 2.0 * x
        slipping[k] = x > 0.0


def stream_round(arrays, budget=2e7) -> float:
    """ns per contact of ``_stream`` over ``arrays`` (``contact_streams``), repeated for about
    ``budget`` contacts."""
    n = arrays[0][0].shape[0]
    reps = max(1, int(budget // n))
    t0 = time.perf_counter()
    for _ in range(reps):
        _stream(*arrays)
    return (time.perf_counter() - t0) / reps / n * 1e9


def stream_ns(n_contacts, rounds=5) -> float:
    """Best ns per contact of ``_stream`` over ``n_contacts`` in ``rounds`` rounds."""
    arrays = contact_streams(n_contacts)
    _stream(*arrays)
    return min(stream_round(arrays) for _ in range(rounds))


# the bonded specimen's contacts at 1e5 and 1e6 blocks (throughput.run, million.py)
MODELS = {623_012: 108_334, 6_247_144: 1_083_334}


def stream_footprints(rounds=7, path=None, reference=False) -> dict:
    """``_stream``'s ns per contact against the contact arrays' size (MB), the sizes in
    alternating order each round; the 1e5- and 1e6-block models' sizes marked. Writes
    stream_footprint.json and .png (``path`` without suffix; default: in
    ``scenes.results_dir(reference)``)."""
    import json
    from pathlib import Path
    contacts = [62_301, 311_506, 623_012, 934_518, 1_246_024, 1_869_036, 2_492_048, 6_247_144]
    arrays = {n: contact_streams(n) for n in contacts}
    _stream(*arrays[contacts[0]])
    times = {n: [] for n in contacts}
    for r in range(rounds):
        for n in (contacts if r % 2 == 0 else contacts[::-1]):
            times[n].append(stream_round(arrays[n], 1.5e7))
    mb = {n: sum(a.nbytes for group in arrays[n] for a in group) / 2 ** 20 for n in contacts}
    out = {"machine": scenes.machine(), "rounds": rounds,
           "rows": [{"contacts": n, "model_blocks": MODELS.get(n),
                     "contact_arrays_MB": round(mb[n], 1),
                     "best_ns": round(min(times[n]), 2),
                     "median_ns": round(float(np.median(times[n])), 2)} for n in contacts]}
    path = Path(path or scenes.results_dir(reference) / "stream_footprint")
    path.with_suffix(".json").write_text(json.dumps(out, indent=2))
    _stream_figure(out["rows"], path.with_suffix(".png"))
    print(json.dumps(out["rows"]), flush=True)
    return out


def _stream_figure(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    x = [r["contact_arrays_MB"] for r in rows]
    ax.plot(x, [r["best_ns"] for r in rows], "o-", label="best of the rounds")
    ax.plot(x, [r["median_ns"] for r in rows], "o:", color="tab:blue", alpha=0.5,
            label="median of the rounds")
    for r in rows:
        if r["model_blocks"]:
            ax.annotate(f"the {r['model_blocks']:,}-block model", (r["contact_arrays_MB"],
                        r["best_ns"]), textcoords="offset points",
                        xytext=(-70, -24) if r["model_blocks"] > 5e5 else (10, -34),
                        fontsize=8, arrowprops=dict(arrowstyle="-", lw=0.6))
    ax.set_xscale("log")
    ax.set_ylim(bottom=0)
    ax.set_xlabel("size of the contact arrays streamed each step (MB)")
    ax.set_ylabel("ns per contact")
    ax.set_title("The contact pass's bytes through a loop of its shape (no arithmetic, "
                 "no block data)", fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def profile(n_blocks, steps=200):
    from dem_core.contact import forces
    from dem_core.step import run as step
    from dem_core.components import add_gravity

    bs = throughput.specimen(n_blocks)
    m = leave_model(bs)
    p, s, c = m.props, m.state, m.contacts
    strength = m.table.strength_array()
    parts = {}

    def timed(name, fn):
        fn()                                   # warm
        t0 = time.perf_counter()
        for _ in range(steps):
            fn()
        parts[name] = (time.perf_counter() - t0) / steps

    timed("zero force array", lambda: s.force.fill(0.0))
    timed("contact forces + law (add_contact_forces)", lambda: forces.add_contact_forces(
        c, strength, s, m.cracks, m.time, m.corners, False, m.zone_state))
    grav = m.parts().gravity
    timed("gravity (add_gravity)", lambda: add_gravity(grav, s, p))
    # advance moves the blocks: keep the force small so the specimen stays put
    s.force.fill(0.0)
    integ = m.integrator()
    timed("damping + integration + rotation + movement check (advance)", lambda: step.advance(
        s, p, integ, m.dt))
    m2 = leave_model(bs)
    m2.cycle(steps)
    t0 = time.perf_counter()
    m2.cycle(steps)
    whole = (time.perf_counter() - t0) / steps
    total = sum(parts.values())
    return {"blocks": bs.n_blocks, "contacts": int(c.n), "whole_step_s": whole,
            "parts_s": parts, "parts_fraction_of_sum": {k: v / total for k, v in parts.items()},
            "ns_per_contact_in_contact_kernel":
                1e9 * parts["contact forces + law (add_contact_forces)"] / c.n}


def leave_model(bs):
    from dem_core.contact.materials import Material
    from dem_core.model import Model

    flaw = Material(kn=40e9, ks=20e9, tensile_strength=1.1e6, cohesion=1.2e6, friction=37)
    m = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=1700, history_every=10**9)
    m.fix("base")
    m.set_gravity(50.0)
    m.cycle(20)
    return m


def continuum(full, log):
    import continuum_scaling as cs
    from continuum_ref.materials import Elastic, MohrCoulomb

    hs = [0.04, 0.02, 0.01] if not full else [0.04, 0.02, 0.01, 0.006]
    rows = []
    for h in hs:
        r = cs.slope_case(h, Elastic(E=2.6e9, nu=0.16), 100.0)
        r.update(law="elastic", s_per_newton_iteration=r["solve_s"] / r["newton_iterations"])
        rows.append(r)
        log(f"  elastic slope h {h}: {r['dofs']} dofs, {r['s_per_newton_iteration']:.4f} s/it")
    for h in (hs[:2] if not full else hs[:3]):
        mat = MohrCoulomb(E=2.6e9, nu=0.16, cohesion=50e3, friction=30.0, dilation=0.0,
                          tensile_strength=20e3)
        r = cs.slope_case(h, mat, 60.0)
        r.update(law="mohr_coulomb", s_per_newton_iteration=r["solve_s"] /
                 max(r["newton_iterations"], 1))
        rows.append(r)
        log(f"  MC slope h {h}: {r['dofs']} dofs, {r['s_per_newton_iteration']:.4f} s/it")
    return rows


def plot(out, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(17, 4.8))
    sc = out["scaling"]
    ax = axes[0]
    for threads, mk in ((1, "o-"), (2, "s--")):
        rows = [r for r in sc if r["threads"] == threads]
        ax.loglog([r["blocks"] for r in rows], [r["contact_updates_per_s_per_core"] for r in rows],
                  mk, label=f"measured, {threads} thread{'s' * (threads > 1)} (per core)")
    lim = out["machine_limit"]["bandwidth_bound_updates_per_s"]
    ax.axhline(lim, color="r", ls="--", label=f"memory-bandwidth bound ({lim:.2g}/s)")
    ax.set_xlabel("blocks")
    ax.set_ylabel("contact updates / s / core")
    ax.set_title("DEM throughput")
    ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)
    ax = axes[1]
    pr = out["profile"]["parts_fraction_of_sum"]
    ax.barh(range(len(pr)), list(pr.values()))
    ax.set_yticks(range(len(pr)))
    ax.set_yticklabels(list(pr), fontsize=7)
    ax.set_xlabel("fraction of the step")
    ax.set_title(f"DEM step profile, {out['profile']['blocks']} blocks")
    ax = axes[2]
    for law, mk in (("elastic", "o-"), ("mohr_coulomb", "s-")):
        rows = [r for r in out["continuum"] if r["law"] == law]
        ax.loglog([r["dofs"] for r in rows], [r["s_per_newton_iteration"] for r in rows], mk,
                  label=law)
    ax.set_xlabel("dofs")
    ax.set_ylabel("s per Newton iteration")
    ax.set_title("continuum (MUMPS LU, serial)")
    ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def machine_limit(n_blocks: int, rounds: int = 3) -> dict:
    """Bandwidth (best of ``rounds``) and the serial step's ns per contact update at
    ``n_blocks`` (best of ``rounds``, 200 steps each) in one run, against the bound
    BYTES_PER_CONTACT / copy bandwidth (issue 29 item 2: within 2x). One JSON line."""
    import json

    bw = max((bandwidth() for _ in range(rounds)), key=lambda b: b["copy_GB_s"])
    runs, streams = [], []
    for _ in range(rounds):            # alternating, so both see the same spells of the host
        runs.append(throughput.run(n_blocks, 200, threads=1))
        streams.append(stream_ns(runs[0]["contacts"], rounds=1))
    ns = min(r["ns_per_contact_update"] for r in runs)
    bound = BYTES_PER_CONTACT / bw["copy_GB_s"]
    out = {"machine": scenes.machine(), "blocks": runs[0]["blocks"],
           "contacts": runs[0]["contacts"], "bandwidth": bw,
           "bytes_per_contact_update": BYTES_PER_CONTACT, "bound_ns_per_update": round(bound, 2),
           "measured_ns_per_update": [r["ns_per_contact_update"] for r in runs],
           "best_over_bound": round(ns / bound, 2),
           # the same bytes through a numba loop of the contact pass's shape (no block data)
           "stream_ns_per_update": [round(t, 2) for t in streams],
           "best_over_stream": round(ns / min(streams), 2),
           "stream_GB_s": round(BYTES_PER_CONTACT / min(streams), 2)}
    print(json.dumps(out), flush=True)
    return out


def main(argv=None):
    ap = scenes.quick_or_full_parser(__doc__.splitlines()[0])
    ap.add_argument("--limit", type=int, metavar="N",
                    help="only the machine limit: the bandwidth and the serial rate at N blocks "
                         "in one run, and how far the rate is from the bandwidth bound")
    ap.add_argument("--rounds", type=int, default=3,
                    help="with --limit: alternating rounds of the step and the stream loop")
    ap.add_argument("--streams", action="store_true",
                    help="only the stream loop against the contact arrays' size "
                         "(stream_footprint.json, .png)")
    a = ap.parse_args(argv)
    if a.streams:
        return stream_footprints(reference=a.reference)
    if a.limit:
        return machine_limit(a.limit, a.rounds)
    out = {"machine": scenes.machine(), "mode": "full" if a.full else "quick",
           "threads": [1, 2],
           "note": "1 thread: serial kernel; 2 threads: dem_core.step.threads.parallel (bit-identical); "
                   "per core = per thread"}
    t0 = time.perf_counter()
    out["bandwidth"] = bandwidth()
    print(f"bandwidth: copy {out['bandwidth']['copy_GB_s']:.1f} GB/s")
    sizes = [1000, 3000, 10_000] if not a.full else [1000, 3000, 10_000, 30_000, 100_000]
    out["scaling"] = []
    out["speedup_2_threads"] = []
    for n in sizes:
        pair = {}
        for threads in (1, 2):
            r = throughput.run(n, 300 if n <= 10_000 else 200, threads=threads)
            out["scaling"].append(r)
            pair[threads] = r
            print(f"  {r['blocks']} blocks, {threads} thread(s): "
                  f"{r['contact_updates_per_s_per_core']:.3g} updates/s/core")
        out["speedup_2_threads"].append(
            {"blocks": pair[1]["blocks"],
             "speedup": pair[1]["seconds_per_step"] / pair[2]["seconds_per_step"]})
    out["profile"] = profile(10_000 if not a.full else 30_000)
    print("  profile:", {k: round(v, 3) for k, v in out["profile"]["parts_fraction_of_sum"].items()})
    bw = out["bandwidth"]["copy_GB_s"] * 1e9
    best = max(r["contact_updates_per_s_per_core"] for r in out["scaling"] if r["threads"] == 1)
    out["machine_limit"] = {
        "bytes_per_contact_update": BYTES_PER_CONTACT, "flops_per_contact_update":
            FLOPS_PER_CONTACT, "bandwidth_bound_updates_per_s": bw / BYTES_PER_CONTACT,
        "bandwidth_bound_ns_per_update": 1e9 * BYTES_PER_CONTACT / bw,
        "measured_best_updates_per_s": best,
        "fraction_of_bandwidth_bound": best / (bw / BYTES_PER_CONTACT),
        "achieved_GB_s": best * BYTES_PER_CONTACT / 1e9,
        "achieved_GFlop_s": best * FLOPS_PER_CONTACT / 1e9}
    print("  machine limit:", {k: (round(v, 3) if isinstance(v, float) else v)
                               for k, v in out["machine_limit"].items()})
    out["continuum"] = continuum(a.full, print)
    out["wall_seconds"] = time.perf_counter() - t0
    path = scenes.write_json("performance", out, a.reference)
    plot(out, scenes.results_dir(a.reference) / "performance.png")
    print(f"wrote {path} ({out['wall_seconds']:.0f} s)")


if __name__ == "__main__":
    main()
