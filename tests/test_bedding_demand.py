"""The bedding-demand benchmark's slip-g arithmetic against hand values."""
import math

import numpy as np
import pytest

from benchmarks.bedding_demand import G_LEVELS, slip_shares


def test_slip_g_follows_the_elastic_scaling():
    # one bed piece: sigma_n = tau = 10 kPa at 10 g; excess 10 - 10 tan 23 = 5.755 kPa, so it
    # needs more than 15 kPa from 10 * 15 / 5.755 = 26.1 g on and more than 5 kPa from 8.7 g on;
    # a second piece (weight 3) is in tension with no shear: never past a cohesion
    sn = np.array([10e3, -1e3])
    ts = np.array([-10e3, 0.0])
    shares = slip_shares(sn, ts, np.array([1.0, 3.0]), 23.0, g=10.0)
    assert 10 * 15 / (10 - 10 * math.tan(math.radians(23))) == pytest.approx(26.06, abs=0.01)
    assert G_LEVELS == (10, 20, 40, 70)
    assert shares["15"] == [0.0, 0.0, 0.25, 0.25]
    assert shares["5"] == [0.25, 0.25, 0.25, 0.25]


def test_friction_alone_holding_a_piece_means_it_never_slips():
    shares = slip_shares(np.array([10e3]), np.array([4e3]), np.array([1.0]), 23.0, g=10.0)
    assert shares == {"5": [0.0] * 4, "15": [0.0] * 4}
