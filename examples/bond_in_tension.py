"""A bonded interface pulled apart breaks at its tensile strength: two 0.1 x 0.05 m blocks glued
by a flaw of T = 1 MPa along their 0.1 m shared edge; the upper one is pulled up slowly. The
peak pull is T x edge length = 100 kN/m (per metre of thickness), within 1 %.
"""
from dem_core.geometry import GeometrySpec, rectangle
from dem_core.contact.materials import Material
from dem_core.workflow.scene import Boundary, Scene, build_model

T, WIDTH = 1e6, 0.1


def main(quick=True):
    geometry = GeometrySpec([rectangle("lower", 0, 0, WIDTH, 0.05),
                             rectangle("upper", 0, 0.05, WIDTH, 0.1)])
    bond = Material(kn=1e11, ks=5e10, tensile_strength=T, cohesion=2 * T, friction=35)
    scene = Scene(geometry, {"*": bond}, density=2500.0,
                  boundaries=[Boundary("lower")], solver={"damping": 0.8})
    model = build_model(scene)
    model.set_velocity("upper", vx=0.0, vy=1e-3 if quick else 2e-4)    # m/s, slow vs waves
    peak = 0.0
    while not model.crack_counts()["tension"]:
        model.cycle(10)
        peak = max(peak, float(-model.state.force[model.group("upper")[0], 1]))
    print(f"peak pull {peak / 1e3:.2f} kN/m, T x L = {T * WIDTH / 1e3:.2f} kN/m")
    assert abs(peak / (T * WIDTH) - 1) < 0.01
    return peak


if __name__ == "__main__":
    main(quick=False)
