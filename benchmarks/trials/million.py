"""A million blocks: tessellation time, model memory and the per-contact rate against 1e5.

    python benchmarks/trials/million.py                      # 1e6 blocks, then 1e5 for the rate
    python benchmarks/trials/million.py --blocks 200000 --steps 20

The bonded Voronoi specimen of ``throughput.py`` (a square of 5 mm cells, 5 Lloyd iterations,
on a fixed base under 50 g). For each size: the tessellation's wall time
(``build_block_system``), the model's set-up time (``Model``: masses, contacts, stiffness,
time step) and the process's resident memory after each; the largest size is built first, so
the peak memory is its own, and the reference's memory is what it added. Then, with both
models alive, ``--rounds`` alternating rounds of ``--steps`` steps of ``Model.cycle`` at the
large size and ten times as many at the reference, on one thread: ns per contact update, and
the ratio of each round's two rates (median and best reported), so both sizes see the same
spells of the shared host. Each round also times ``performance._stream`` over each size's
contact count (the contact pass's bytes through a loop of its shape, no block data): its
1e6 / 1e5 ratio is what the memory system alone gives between the two footprints
(docs/performance.md, "A million blocks"); and it times the model's serial contact pass on the
reference's contacts and blocks, once as they are and once copied side by side to the large
size (``tiled``): the size of the contact streams with the reference's locality. Issue 29's goals: tessellation under 5 minutes,
the model under 8 GB, the same per-contact rate as at 1e5 blocks. Writes
``results/benchmarks/million.json`` and ``million.png`` (the committed record:
``benchmarks/results/million.json``, ``.png``).
"""
from __future__ import annotations

import argparse
import functools
import json
import os
import resource
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
BENCHMARKS = os.path.dirname(HERE)        # a trial uses the benchmarks' modules (trials/README.md)
sys.path.insert(0, BENCHMARKS)

import outdir  # noqa: E402


def huge_gb() -> float:
    """Resident memory of this process in transparent huge pages now, GB (0 where the kernel
    has none): large arrays in 4 kB pages cost a TLB miss per page touched."""
    try:
        with open("/proc/self/smaps_rollup") as f:
            for line in f:
                if line.startswith("AnonHugePages:"):
                    return int(line.split()[1]) * 1024 / 1e9
    except OSError:
        pass
    return 0.0


def rss_gb() -> float:
    """Resident memory of this process now, GB."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 1e9


def peak_gb() -> float:
    """Highest resident memory of this process so far, GB (Linux: ru_maxrss in kB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 / 1e9


def build(n_blocks):
    """The specimen's model at about ``n_blocks`` blocks after a 20-step warm-up, and its row:
    tessellation and set-up seconds, resident memory before and after (GB)."""
    from dem_core.contact.materials import Material
    from dem_core.model import Model

    from throughput import specimen
    row = {"target_blocks": n_blocks, "rss_start_gb": round(rss_gb(), 3)}
    t0 = time.perf_counter()
    bs = specimen(n_blocks)
    row["tessellation_s"] = round(time.perf_counter() - t0, 1)
    row["blocks"] = int(bs.n_blocks)
    row["rss_after_tessellation_gb"] = round(rss_gb(), 3)
    flaw = Material(kn=40e9, ks=20e9, tensile_strength=1.1e6, cohesion=1.2e6, friction=37)
    t0 = time.perf_counter()
    m = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=1700, history_every=10**9)
    m.fix("base")
    m.set_gravity(50.0)
    row["model_setup_s"] = round(time.perf_counter() - t0, 1)
    row["contacts"] = int(m.contacts.n)
    row["rss_with_model_gb"] = round(rss_gb(), 3)
    row["peak_rss_gb"] = round(peak_gb(), 3)
    m.cycle(20)
    return m, row


def ns_per_update(m, steps) -> float:
    """ns per contact update of ``steps`` steps of ``Model.cycle`` on ``m``."""
    t0 = time.perf_counter()
    m.cycle(steps)
    return 1e9 * (time.perf_counter() - t0) / (m.contacts.n * steps)


def tiled(m, copies):
    """The contacts and blocks of model ``m`` copied ``copies`` times side by side in memory
    (the i-th copy's blocks numbered after the (i-1)-th's, no contact between copies): a
    (Contacts, BlockState) pair as large as a model ``copies`` times bigger, with ``m``'s
    locality. What the size of the contact streams alone costs the contact pass."""
    c, s, nb = m.contacts, m.state, m.n_blocks
    n = int(c.count[0])
    fields = {}
    for name in c._fields:
        x = getattr(c, name)
        if name == "count":
            fields[name] = np.array([n * copies], x.dtype)
        elif name in ("block_a", "block_b"):
            fields[name] = np.concatenate([x[:n] + i * nb for i in range(copies)]).astype(x.dtype)
        elif name == "partner":
            fields[name] = np.concatenate([np.where(x[:n] >= 0, x[:n] + i * n, -1)
                                           for i in range(copies)]).astype(x.dtype)
        else:
            fields[name] = np.ascontiguousarray(np.concatenate([x[:n]] * copies))
    blocks = {name: np.ascontiguousarray(np.concatenate([getattr(s, name)] * copies))
              for name in s._fields}
    return type(c)(**fields), type(s)(**blocks)


def contact_pass_ns(c, s, m, reps) -> float:
    """ns per contact of ``reps`` calls of the model's serial contact pass
    (``forces.add_contact_forces``) on contacts ``c`` and blocks ``s`` of ``m``'s materials."""
    t0 = time.perf_counter()
    _contacts_serial()(reps, c, m.table.strength_array(), s, m.cracks, m.corners, m.zone_state)
    return 1e9 * (time.perf_counter() - t0) / (reps * int(c.count[0]))


@functools.lru_cache(maxsize=None)
def _contacts_serial():
    """``two_threads``'s loop of serial contact passes, built once (compiled on first call)."""
    from two_threads import _loops
    return _loops()[0]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=1_000_000)
    ap.add_argument("--reference", type=int, default=100_000,
                    help="the size whose per-contact rate is the reference")
    ap.add_argument("--steps", type=int, default=30,
                    help="steps a round at --blocks (the reference: ten times as many)")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--out", default=str(outdir.OUT))
    a = ap.parse_args()
    from performance import contact_streams, stream_round, _stream
    from scenes import machine
    big_m, big = build(a.blocks)          # the largest first: the peak memory is its own
    print(json.dumps(big), flush=True)
    ref_m, ref = build(a.reference)
    ref["rss_added_gb"] = round(rss_gb() - big["rss_with_model_gb"], 3)
    print(json.dumps(ref), flush=True)
    streams = {}
    for row in (big, ref):
        streams[row["blocks"]] = contact_streams(row["contacts"])
        _stream(*streams[row["blocks"]])
    copies = max(1, round(big["contacts"] / ref["contacts"]))
    one = (ref_m.contacts, ref_m.state)
    many = tiled(ref_m, copies)
    contact_pass_ns(*one, ref_m, 1)              # compiled (or loaded) before the rounds
    # alternating rounds, so both sizes see the same spells of the host (it is shared)
    for _ in range(a.rounds):
        for row, m, steps in ((big, big_m, a.steps), (ref, ref_m, 10 * a.steps)):
            row.setdefault("ns_per_contact_update", []).append(round(ns_per_update(m, steps), 2))
            row.setdefault("stream_ns_per_contact", []).append(
                round(stream_round(streams[row["blocks"]]), 2))
        for key, (c, s) in (("tiled", many), ("one_copy", one)):
            ref.setdefault(f"contact_pass_ns_{key}", []).append(
                round(contact_pass_ns(c, s, ref_m, max(1, int(2e7 // int(c.count[0])))), 2))
    ref["tiled_copies"] = copies
    for row in (big, ref):
        row.update(steps_a_round=a.steps * (1 if row is big else 10),
                   huge_pages_gb=round(huge_gb(), 3))

    def ratio(key, how):
        pairs = zip(big[key], ref[key])
        return round(float(how([x / y for x, y in pairs])), 3)
    summary = {"machine": machine(), "rounds": a.rounds, "rows": [big, ref],
               # each round's ratio (its two runs next to each other in time): median, best
               "rate_ratio": ratio("ns_per_contact_update", np.median),
               "rate_ratio_best": round(min(big["ns_per_contact_update"])
                                        / min(ref["ns_per_contact_update"]), 3),
               "stream_ratio": ratio("stream_ns_per_contact", np.median),
               "stream_ratio_best": round(min(big["stream_ns_per_contact"])
                                          / min(ref["stream_ns_per_contact"]), 3),
               # the model's contact pass on the reference copied to the large size / on one
               "tiled_ratio": round(float(np.median(
                   [x / y for x, y in zip(ref["contact_pass_ns_tiled"],
                                          ref["contact_pass_ns_one_copy"])])), 3),
               "tiled_ratio_best": round(min(ref["contact_pass_ns_tiled"])
                                         / min(ref["contact_pass_ns_one_copy"]), 3),
               "goals": {"tessellation_under_5_min": big["tessellation_s"] < 300,
                         "model_under_8_gb": big["peak_rss_gb"] < 8.0}}
    print(json.dumps({k: summary[k] for k in summary if "ratio" in k or k == "goals"}))
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "million.json"), "w") as f:
        json.dump(summary, f, indent=1)
    figure(summary, os.path.join(a.out, "million.png"))


def figure(summary, path):
    """Three panels, each size side by side against its goal: the tessellation and set-up
    times (goal: tessellation under 5 minutes), the memory with the model and at its peak
    (goal: under 8 GB), and the ns per contact update of the step and of the stream loop."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = sorted(summary["rows"], key=lambda r: r["blocks"])
    big = rows[-1]
    names = [f"{r['blocks']:,} blocks" for r in rows]
    x = range(len(rows))
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2))
    ax = axes[0]
    ax.bar([i - 0.2 for i in x], [r["tessellation_s"] for r in rows], 0.4, label="tessellation")
    ax.bar([i + 0.2 for i in x], [r["model_setup_s"] for r in rows], 0.4, label="model set-up")
    ax.axhline(300, color="tab:red", ls="--", lw=1, label="goal: tessellation under 5 min")
    ax.set_ylabel("seconds")
    ax.set_title("time to build", fontsize=10)
    ax = axes[1]
    ax.bar([i - 0.2 for i in x], [r.get("rss_added_gb", r["rss_with_model_gb"]) for r in rows],
           0.4, label="resident, the model (the smaller: what it added)")
    ax.bar([len(rows) - 1 + 0.2], [big["peak_rss_gb"]], 0.4,
           label="peak of the process (during the set-up)")
    ax.axhline(8.0, color="tab:red", ls="--", lw=1, label="goal: model under 8 GB")
    ax.set_ylabel("GB")
    ax.set_title("memory", fontsize=10)
    ax = axes[2]
    for shift, key, label in (
            (-0.2, "ns_per_contact_update", f"the step (large / small, median of the rounds: "
                                            f"{summary['rate_ratio']:.2f}x)"),
            (0.2, "stream_ns_per_contact", f"its bytes alone, stream loop "
                                           f"({summary['stream_ratio']:.2f}x)")):
        best = [min(r[key]) for r in rows]
        med = [float(np.median(r[key])) for r in rows]
        ax.bar([i + shift for i in x], best, 0.4, label=label)
        ax.plot([i + shift for i in x], med, "_", color="k", ms=14)
    ax.set_ylabel("ns per contact update, one thread\n(bar: best of the rounds; tick: median)")
    title = "rate (goal: the same at both sizes)"
    if "tiled_ratio" in summary:
        title += (f"\nthe smaller model's contact pass, copied\nto the large size / one "
                  f"copy: {summary['tiled_ratio']:.2f}x")
    ax.set_title(title, fontsize=9)
    for ax in axes:
        ax.set_xticks(list(x), names, fontsize=8)
        ax.legend(fontsize=7, loc="upper left")
        ax.set_ylim(0, ax.get_ylim()[1] * 1.35)
        ax.grid(axis="y", alpha=0.3)
    fig.suptitle(f"Bonded Voronoi specimen, {summary['machine']['cpu']}, "
                 f"{summary['machine']['date']}, {summary['rounds']} alternating rounds",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
