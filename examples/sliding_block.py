"""A block on an inclined plane slides with the Coulomb acceleration g (sin theta - cos theta
tan phi) when theta > phi (here theta 30, phi 20 degrees: 1.81 m/s^2).

The plane is horizontal and gravity is tilted by theta, so the block slides along x. Two
regions, a 20 m base and a 1 x 0.5 m block, meet on a frictional interface (the contact
material "boundary:base|block"); no damping, so the motion is the dynamics of the law.
"""
import math

from dem_core.geometry import GeometrySpec, rectangle
from dem_core.contact.materials import Material
from dem_core.workflow.scene import Boundary, Scene, build_model
from dem_core.workflow.stages import Cycle, Gravity, run_stages

THETA, PHI = 30.0, 20.0


def main(quick=True):
    geometry = GeometrySpec([rectangle("base", 0, 0, 20, 1), rectangle("block", 2, 1, 3, 1.5)])
    th = math.radians(THETA)
    scene = Scene(geometry, {"*": Material(kn=1e9, ks=1e9, friction=PHI)},
                  density=2000.0, boundaries=[Boundary("base")], points={"block": (2.5, 1.25)},
                  stages=[Gravity(1.0, direction=(math.sin(th), -math.cos(th))),
                          Cycle(2000 if quick else 20_000)],
                  solver={"damping": 0.0})
    model = build_model(scene)
    record = run_stages(model, scene.stages)[-1]
    ux, t = record.points["block"][0], record.time
    accel = 2 * ux / t ** 2                                   # x = a t^2 / 2 from rest
    expected = 9.81 * (math.sin(th) - math.cos(th) * math.tan(math.radians(PHI)))
    print(f"slid {ux:.3f} m in {t:.3f} s: a = {accel:.4f} m/s^2, closed form {expected:.4f}")
    assert abs(accel / expected - 1) < 0.01
    return accel


if __name__ == "__main__":
    main(quick=False)
