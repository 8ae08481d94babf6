"""Thesis scenes as data: geometry, materials and boundary conditions, one module per case."""

import functools

from dem_core._moved import renamed
from dem_core.workflow.scene import Boundary

# case parameters that were renamed: old name -> new name. The old names are still accepted
# (a sweep member's params, ``XParams(flaw_tensile=...)``, ``p.with_(flaw_tensile=...)``) for
# one release, with a DeprecationWarning naming the new one.
RENAMED_PARAMS = {"flaw_tensile": "flaw_tensile_strength"}


def new_param_names(params: dict, where: str = "params") -> dict:
    """``params`` with each old name (``RENAMED_PARAMS``) renamed, warning for each
    (DeprecationWarning naming the new name); TypeError when both names are given."""
    return renamed(params, RENAMED_PARAMS, where, "parameter", TypeError)


def old_param_names(cls):
    """Class decorator of a case's parameter dataclass: its constructor and ``with_`` also
    take the old names of renamed parameters (``new_param_names``)."""
    init, with_ = cls.__init__, cls.with_

    @functools.wraps(init)
    def __init__(self, *args, **kwargs):
        init(self, *args, **new_param_names(kwargs, cls.__name__))

    @functools.wraps(with_)
    def with_new_names(self, **changes):
        return with_(self, **new_param_names(changes, f"{cls.__name__}.with_"))

    cls.__init__, cls.with_ = __init__, with_new_names
    return cls

# The centrifuge models' boundaries (thesis fig 4.8, assumed for both cases): the base fixed
# (the blocks touching y = 0), rollers on both sides (the blocks touching x = 0 and x = width
# hold x, free in y and rotation).
CENTRIFUGE_GROUPS = {"base": {"touching": "bottom"}, "left side": {"touching": "left"},
                     "right side": {"touching": "right"},
                     "side walls": {"union": ["left side", "right side"]},
                     "sides": {"minus": ["side walls", "base"]}}
CENTRIFUGE_BOUNDARIES = [Boundary("base"), Boundary("sides", x=True, y=False, rotation=False)]
