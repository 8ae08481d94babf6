"""The explicit time step and the state it advances.

Holds: ``state`` (the state bundles), ``kinematics`` (rigid-body helpers every kernel uses),
``run`` (the step: ``run_steps``, serial and threaded), ``integration`` (damping, leapfrog,
movement checks: of blocks, support nodes and gridpoints), ``relaxation`` (kinetic damping),
``nodes`` (the update of support nodes),
``critical_step`` (the eigenvalue step estimate), ``threads/`` (the step on several threads).

May import: numpy, numba, ``dem_core.contact``, ``dem_core.components``,
``dem_core.deformable`` (their kernels). Never the driver, the workflow or the output.

``dem_core.step.run_steps`` and the other names of ``step.run`` are also read from here (the
path they had before the subpackages), loaded on first use so that importing a kernel of
``step`` does not import the whole step.
"""
from __future__ import annotations

import importlib
import warnings

_SUBMODULES = {"state", "kinematics", "run", "integration", "relaxation", "nodes",
               "critical_step", "threads"}


def __getattr__(name):
    # a submodule not yet imported: let the import system import it
    if name in _SUBMODULES or name.startswith("__"):
        raise AttributeError(name)
    run = importlib.import_module(__name__ + ".run")
    if not hasattr(run, name):
        raise AttributeError(f"module 'dem_core.step' has no attribute {name!r}")
    warnings.warn(f"dem_core.step.{name} moved to dem_core.step.run.{name}; the old path goes "
                  "in the next release", DeprecationWarning, stacklevel=2)
    return getattr(run, name)
