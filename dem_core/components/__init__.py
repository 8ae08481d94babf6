"""Force components of the time step. Holds gravity, applied loads, the servo, water pressure,
cables and liners (and ``support``: the Cable and Liner records a scene installs), each a small bundle of flat arrays and one kernel with
the signature ``add_forces(bundle, state, props)`` (``state.BlockState``, ``state.BlockProps``)
that adds into ``state.force`` (or, for the servo, sets prescribed velocities from it).

A component a scene does not use is its empty bundle (zero rows): its kernel loops over
nothing, so an unused component costs nothing measurable (``benchmarks/leave_out.py``).
Components that add stiffness (cables, liners) add their springs to the blocks' frequency
bound for the automatic time step (``support.support_stiffness``); their kernels compute forces
only (on the blocks and on their own nodes), and the nodes are advanced by the step's one
integration (``step.integration.advance_nodes``), with inertial masses that keep them inside
that step (``support.set_node_masses``).

| component | bundle | kernel |
|---|---|---|
| gravity (and the centrifuge g-level) | ``Gravity`` | ``add_gravity`` |
| applied constant loads | ``Loads`` | ``add_loads`` |
| water table: pressure on contacts and exposed faces | ``Water`` | ``add_water`` |
| grouted cables and rock bolts | ``Cables`` | ``add_cables`` |
| shotcrete liners | ``Liners`` | ``add_liners`` |
| servo-controlled groups (constant force) | ``Servo`` | ``servo_velocities`` |
| deformable blocks' zones (floating frame) | ``deformable.Deformable`` | ``deformable.add_deformable`` |

``deformable`` is imported as ``dem_core.deformable.component`` (not from this package: it
imports ``dem_core.deformable.zones``, which imports ``components.nodes``). Its kernel also takes the
contacts, and the contact kernels read its bundle (the contact points move with the zones).

May import: numpy, numba, ``dem_core.step`` (kinematics, nodes, state), ``dem_core.contact``.
Never the driver, the workflow or the output.
"""
from .cables import Cables, add_cables, no_cables
from .liner import Liners, add_liners, no_liners
from .gravity import Gravity, add_gravity, gravity_bundle
from .loads import Loads, add_loads, loads_bundle
from .servo import Servo, servo_bundle, servo_velocities
from .water import Water, add_water, exposed_faces, no_water, water_bundle

__all__ = ["Gravity", "add_gravity", "gravity_bundle", "Loads", "add_loads", "loads_bundle",
           "Servo", "servo_bundle", "servo_velocities", "Water", "add_water", "water_bundle",
           "no_water", "exposed_faces", "Cables", "add_cables", "no_cables", "Liners",
           "add_liners", "no_liners"]
