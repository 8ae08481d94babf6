"""The README's slope: Adhikary & Dyskin's centrifuge model of flexural toppling, raised in g
until it fails (thesis 4.2; experiment 80-85 g, thesis UDEC-DM 70 g at T = 1.1 MPa).

The scene is data: a 0.33 m slope at 61 degrees cut by 10 mm beds dipping 81 degrees into the
slope, Voronoi flaws in the columns, a fixed base and rollers on the sides, points A (crest)
and B (mid-face), and one stage: a g-ramp. ``quick=False`` runs the thesis's base run, the
scene file comparisons/scenes/adhikary.json (6 mm blocks, 10 g levels bisected to 1 g);
``main(quick=True)`` the same scene with 8 mm blocks in 20 g steps. The failure g falls with the
block size (85 / 76 / 54 g at 8 / 6 / 4 mm: docs/verification.md), so the assertion allows
the experiment's 80-85 g -25 % / +25 %.
"""
from pathlib import Path

from comparisons.scenes import adhikary
from dem_core.workflow.scene import Scene, build_model
from dem_core.workflow.stages import RaiseGravity, run_stages

SCENE = Path(adhikary.__file__).with_name("adhikary.json")

EXPERIMENT_G = (80.0, 85.0)


def main(quick=True):
    scene = Scene.load(SCENE)
    if quick:
        # failed: A or B moves 5 mm in one level, or keeps moving (> 0.2 mm over its last fifth)
        ramp = RaiseGravity((40.0, 60.0, 80.0, 100.0, 120.0), ratio=1e-5, max_steps=25_000,
                            failure_displacement=0.005, creep=2e-4, watch=("A", "B"))
        params = adhikary.AdhikaryParams(edge_length=0.008, relax_iterations=5)
        scene = adhikary.scene(params, stages=[ramp])
    model = build_model(scene)
    record = run_stages(model, scene.stages)[-1]
    failure_g = record.detail["failure_g"]
    print(f"{model.n_blocks} blocks: failed at {failure_g} g (last stable "
          f"{record.detail['last_stable_g']} g), {model.crack_counts()}, {record.seconds:.0f} s")
    assert failure_g is not None and 0.75 * EXPERIMENT_G[0] <= failure_g <= 1.25 * EXPERIMENT_G[1]
    return failure_g


if __name__ == "__main__":
    main(quick=False)
