"""What the step from the largest eigenvalue costs and gains, against the model's size.

    python benchmarks/critical_step_cost.py [--quick | --full]

For the bonded Voronoi specimen of ``throughput.py`` (1e3 and 1e4 blocks; ``--full`` adds
1e5), with mass scaling as a quasi-static run has it: the critical step bounded block by block
(``step_estimate="bound"``, ``step.frequency_bound``) and from the largest eigenvalue
("eigen", ``critical_step.largest_omega2``), their ratio (the gain in steps for the same
safety), the seconds of one eigenvalue solve (best of three) and of one step (best of three
runs of 200 steps), and the solve's cost in steps. A run pays one solve per contact search that
changes the contacts. Writes results/benchmarks/critical_step_cost.json
and .png (``--reference``: benchmarks/results/).
"""
from __future__ import annotations

import time

import scenes
from throughput import specimen


def measure(n_blocks: int) -> dict:
    from dem_core.step import critical_step
    from dem_core.contact.materials import Material
    from dem_core.model import Model

    bs = specimen(n_blocks)
    flaw = Material(kn=40e9, ks=20e9, tensile_strength=1.1e6, cohesion=1.2e6, friction=37)
    row = {"blocks": bs.n_blocks}
    for est in ("bound", "eigen"):
        m = Model(bs, {"flaw:*": flaw, "boundary:*": flaw}, density=1700, mass_scaling=True,
                  history_every=10**9, step_estimate=est)
        m.fix("base")
        row[f"critical_dt_{est}"] = m.critical_dt
    m.set_gravity(50.0)
    m.cycle(20)                                   # compile or load the cache
    solve, step = [], []
    for _ in range(3):
        t0 = time.perf_counter()
        critical_step.largest_omega2(m.contacts, m.state, m.props)
        solve.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        m.cycle(200)
        step.append((time.perf_counter() - t0) / 200)
    row.update(contacts=int(m.contacts.n), gain=row["critical_dt_eigen"] / row["critical_dt_bound"],
               solve_s=min(solve), step_s=min(step), solve_in_steps=min(solve) / min(step))
    return row


def figure(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = [r["blocks"] for r in rows]
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    a.loglog(n, [r["solve_s"] for r in rows], "o-", label="one eigenvalue solve")
    a.loglog(n, [r["step_s"] for r in rows], "s-", label="one step")
    a.set_xlabel("blocks")
    a.set_ylabel("seconds (best of three)")
    a.legend()
    a.grid(alpha=0.3, which="both")
    a.set_title("cost", fontsize=10)
    b.semilogx(n, [r["gain"] for r in rows], "o-")
    b.set_xlabel("blocks")
    b.set_ylabel("critical step: eigen / bound")
    b.set_ylim(1, None)
    b.grid(alpha=0.3, which="both")
    b.set_title("gain in step size at the same safety", fontsize=10)
    fig.suptitle("The critical step from the largest eigenvalue (bonded Voronoi specimen, "
                 "mass scaling)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    a = scenes.quick_or_full_parser(__doc__.splitlines()[0]).parse_args()
    sizes = [1_000, 10_000] + ([100_000] if a.full else [])
    rows = []
    for n in sizes:
        rows.append(measure(n))
        print(rows[-1], flush=True)
    path = scenes.write_json("critical_step_cost", {"machine": scenes.machine(), "rows": rows},
                             a.reference)
    figure(rows, path.with_suffix(".png"))


if __name__ == "__main__":
    main()
