"""What the division of interfaces among their contacts (``dem_core/contact/division.py``) costs,
side by side with the step and the contact search it runs in.

    python benchmarks/division_cost.py --blocks 100000        # one JSON line per size
    python benchmarks/division_cost.py --blocks 1000 10000 100000

The specimen is benchmarks/throughput.py's bonded Voronoi square under 50 g. The division runs
at each contact search; its worst case, timed here, is every pair of the model to be divided
(every contact marked as made by the search, so no pair is skipped). Reported: the step's time
(``Model.cycle``, no search), one search (which includes the division: every pair is looked at
and the unchanged ones left as they are), the division alone (worst case), and the division's
share of the step when searches come every ``steps_per_search`` steps (a search runs once some
block has moved half the search margin: tens to thousands of steps apart in the cases;
``--steps-per-search``, default 100).
"""
from __future__ import annotations

import argparse
import json
import platform
import time

import numpy as np


def measure(n_blocks, steps=50, steps_per_search=10, repeats=3):
    from throughput import loaded, specimen
    from dem_core.contact.contacts import UNBONDED
    from dem_core.contact.division import divide_interfaces
    from dem_core.contact.update import search_contacts

    bs = specimen(n_blocks)
    m = loaded(bs, divide_interfaces=True)
    m.cycle(20)                                         # compile / load the caches
    t0 = time.perf_counter()
    m.cycle(steps)
    t_step = (time.perf_counter() - t0) / steps
    world = m.world()
    c = world.contacts
    bonded = np.zeros(len(m.table.names), np.bool_)     # no pair held by a bond
    divide_interfaces(c, world.state, world.props, bonded, world.corners,
                      m.search_margin)                  # compile
    t_search = min(_timed(lambda: search_contacts(m.world(), m.table, -1, m.search_margin,
                                                  m._moduli(), divide=True))
                   for _ in range(repeats))
    c.broken[:c.n] = UNBONDED                           # the worst case: every pair divided
    t_div = min(_timed(lambda: divide_interfaces(c, world.state, world.props, bonded,
                                                 world.corners, m.search_margin))
                for _ in range(repeats))
    return {"blocks": int(bs.n_blocks), "contacts": int(c.n),
            "step_s": round(t_step, 6), "search_s": round(t_search, 6),
            "division_worst_s": round(t_div, 6),
            "division_over_search": round(t_div / t_search, 3),
            "steps_per_search": steps_per_search,
            "division_share_of_step": round(t_div / (steps_per_search * t_step), 4),
            "machine": platform.processor() or platform.machine()}


def _timed(fn):
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, nargs="+", default=[100_000])
    ap.add_argument("--steps-per-search", type=int, default=100)
    a = ap.parse_args()
    for n in a.blocks:
        print(json.dumps(measure(n, steps_per_search=a.steps_per_search)), flush=True)


if __name__ == "__main__":
    main()
