"""Model files carry a format version (``dem_core.output.io.FORMAT``): a file of today's format
resumes bit for bit, a file of format 1 (written before the version, with the options as
attributes) is converted and resumes bit for bit too, and a file of an unknown format is
refused with a message naming the file and its version."""
import json
import zipfile

import numpy as np
import pytest

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


def rewrite_meta(path, change):
    """The file at ``path`` with its JSON meta changed by ``change(meta) -> meta``."""
    with np.load(path) as z:
        d = {k: z[k] for k in z.files}
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
    m.save(tmp_path / "old.npz")
    rewrite_meta(tmp_path / "old.npz", as_format_1)
    back = Model.load(tmp_path / "old.npz")
    assert back.damping == 0.7 and back.kinetic_damping == 50 and back.fixed_dt is None
    assert back.history.every == m.history.every
    assert same_run(m, back)


def test_a_file_of_an_unknown_format_is_refused_naming_it(tmp_path):
    column().save(tmp_path / "new.npz")
    rewrite_meta(tmp_path / "new.npz", lambda meta: dict(meta, format=io.FORMAT + 1))
    with pytest.raises(ValueError, match=rf"new.npz: a model file of format {io.FORMAT + 1}"):
        Model.load(tmp_path / "new.npz")
