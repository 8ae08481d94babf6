"""Force components of the time step, each a small bundle of flat arrays and one kernel with
the signature ``add_forces(bundle, state, props)`` (``state.BlockState``, ``state.BlockProps``)
that adds into ``state.force`` (or, for the servo, sets prescribed velocities from it).

A component a scene does not use is its empty bundle (zero rows): its kernel loops over
nothing, so an unused component costs nothing measurable (``benchmarks/leave_out.py``).
Components that add stiffness (cables, liners: later) also give a bound of their frequency for
the automatic time step.

| component | bundle | kernel |
|---|---|---|
| gravity (and the centrifuge g-level) | ``Gravity`` | ``add_gravity`` |
| applied constant loads | ``Loads`` | ``add_loads`` |
| water table: pressure on contacts and exposed faces | ``Water`` | ``add_water`` |
| servo-controlled groups (constant force) | ``Servo`` | ``servo_velocities`` |
"""
from .gravity import Gravity, add_gravity, gravity_bundle
from .loads import Loads, add_loads, loads_bundle
from .servo import Servo, servo_bundle, servo_velocities
from .water import Water, add_water, exposed_faces, no_water, water_bundle

__all__ = ["Gravity", "add_gravity", "gravity_bundle", "Loads", "add_loads", "loads_bundle",
           "Servo", "servo_bundle", "servo_velocities", "Water", "add_water", "water_bundle",
           "no_water", "exposed_faces"]
