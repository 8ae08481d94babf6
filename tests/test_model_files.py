"""Model files carry a format version (``dem_core.output.io.FORMAT``): a file of today's format
resumes bit for bit, a file of format 1 (written before the version, with the options as
attributes) or 2 (with the support and zone bundles' own ``control`` clocks) is converted and
resumes bit for bit too, and a file of an unknown format is refused with a message naming the
file and its version."""
import json
import zipfile

import numpy as np
import pytest

from dem_core.components.support import Cable
from dem_core.contact.materials import Material
from dem_core.geometry.simple_blocks import brick_grid
from dem_core.model import Model
from dem_core.output import io


def column():
    bs = brick_grid(1, 3, 0.1, 0.1)
    m = Model(bs, {"flaw:*": Material(kn=1e9, ks=1e9, tensile_strength=2e3, cohesion=2e3,
                                      friction=30)}, density=2500.0, damping=0.7,
              kinetic_damping=50)
    m.fix("bottom")
    m.set_gravity(40.0)
    m.add_history_point("top", (0.05, 0.25))
    m.cycle(300)
    return m


def bolted_column():
    """``column`` with a grouted bolt through its three blocks, run on."""
    m = column()
    m.install(Cable((0.05, 0.02), (0.05, 0.28), area=1e-5, E=2e11, yield_tension=1e5,
                    grout_stiffness=1e9, grout_strength=1e6, segment_length=0.05))
    m.cycle(200)
    return m


def rewrite_meta(path, change, arrays=None):
    """The file at ``path`` with its JSON meta changed by ``change(meta) -> meta`` (and the
    ``arrays`` {name: array} added)."""
    with np.load(path) as z:
        d = {k: z[k] for k in z.files}
    d.update(arrays or {})
    meta = change(json.loads(bytes(d["meta"]).decode()))
    d["meta"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    with open(path, "wb") as fh:
        np.savez(fh, **d)


def as_format_1(meta):
    """The meta a model file had before the format version: the options under "settings" as
    the model's attributes (the fixed step as ``fixed_dt``), no history interval option."""
    opts = meta.pop("options")
    opts["fixed_dt"] = opts.pop("dt")
    opts.pop("history_every")
    meta.pop("format")
    meta["settings"] = opts
    return meta


def old_controls(m):
    """The ``control`` arrays formats 1 and 2 kept in the cables', liners' and zones' bundles:
    dt, damping, time (the support's clock) and gravity, copied from the model."""
    return {"cables.control": np.array([m.dt, m.damping, m.time]),
            "liners.control": np.array([m.dt, m.damping, m.time, *m.gravity]),
            "zone_state.control": np.array([m.dt, m.damping, *m.gravity])}


def same_run(a, b, steps=400):
    a.cycle(steps)
    b.cycle(steps)
    return (np.array_equal(a.state.pos, b.state.pos) and a.time == b.time
            and np.array_equal(a.contacts.sn[:a.contacts.n], b.contacts.sn[:b.contacts.n]))


def test_a_saved_model_carries_the_format_and_resumes_bit_for_bit(tmp_path):
    m = column()
    m.save(tmp_path / "m.npz")
    with zipfile.ZipFile(tmp_path / "m.npz") as z:
        assert "meta.npy" in z.namelist()
    with np.load(tmp_path / "m.npz") as z:
        assert json.loads(bytes(z["meta"]).decode())["format"] == io.FORMAT
    back = Model.load(tmp_path / "m.npz")
    assert back.options == m.options.replace(block_E=back.options.block_E,
                                             block_nu=back.options.block_nu)
    assert back.damping == 0.7 and back.kinetic_damping == 50
    assert same_run(m, back)


def test_a_format_1_file_is_converted_and_resumes_bit_for_bit(tmp_path):
    m = column()
    m.set_options(kinetic_adaptive=False)       # an old file's model checked at fixed intervals
    m.save(tmp_path / "old.npz")
    rewrite_meta(tmp_path / "old.npz", as_format_1, old_controls(m))
    back = Model.load(tmp_path / "old.npz")
    assert back.damping == 0.7 and back.kinetic_damping == 50 and back.fixed_dt is None
    assert back.history.every == m.history.every
    assert same_run(m, back)


def test_a_format_2_file_is_converted_and_resumes_bit_for_bit_with_support(tmp_path):
    """Format 2 kept the support's and the zones' clocks (``control``); format 3 leaves them
    in the file: the step gives every node its dt, damping, time and gravity."""
    m = bolted_column()
    m.set_options(kinetic_adaptive=False)
    m.save(tmp_path / "old.npz")
    rewrite_meta(tmp_path / "old.npz", lambda meta: dict(meta, format=2), old_controls(m))
    back = Model.load(tmp_path / "old.npz")
    assert "control" not in back.cables._fields + back.liners._fields + back.zone_state._fields
    assert back.cables.node_pos.shape[0] > 2
    assert same_run(m, back)
    assert np.array_equal(m.cables.node_pos, back.cables.node_pos)
    assert np.array_equal(m.cables.seg_force, back.cables.seg_force)


def test_a_format_4_file_goes_on_with_the_fixed_kinetic_damping_interval(tmp_path):
    """Format 4 had no ``kinetic_adaptive`` and a kinetic-damping memory of three numbers:
    such a file resumes as it ran, checking every ``kinetic_damping`` steps."""
    m = bolted_column()
    m.set_options(kinetic_adaptive=False)
    m.restart_kinetic_interval()
    m.save(tmp_path / "old.npz")

    def as_format_4(meta):
        meta["options"].pop("kinetic_adaptive")
        return dict(meta, format=4)

    with np.load(tmp_path / "old.npz") as z:
        kinetic = z["array.kinetic"][:3].copy()
    rewrite_meta(tmp_path / "old.npz", as_format_4,
                 {"array.kinetic": kinetic})
    back = Model.load(tmp_path / "old.npz")
    assert back.kinetic_adaptive is False and back.kinetic.shape == (8,)
    assert same_run(m, back)


def test_a_file_of_an_unknown_format_is_refused_naming_it(tmp_path):
    column().save(tmp_path / "new.npz")
    rewrite_meta(tmp_path / "new.npz", lambda meta: dict(meta, format=io.FORMAT + 1))
    with pytest.raises(ValueError, match=rf"new.npz: a model file of format {io.FORMAT + 1}"):
        Model.load(tmp_path / "new.npz")
