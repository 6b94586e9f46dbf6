import math

import numpy as np
import pytest

from envs.world.robot import COMPASSES, GyroCompass, reading


def test_the_error_stream_is_the_same_however_it_is_read():
    whole = GyroCompass.part("mpu9250", dt=0.1, seed=4).errors(3000)
    pieces = GyroCompass.part("mpu9250", dt=0.1, seed=4)
    for n in (1, 7, 500, 2999, 3000):
        assert np.array_equal(pieces.errors(n), whole[:n])
    assert pieces.error(1234) == whole[1234]


def test_the_mpu9250_drifts_as_its_datasheet_says():
    """Over 20 minutes the heading error's spread across power-ons is about what the figures
    give: angle random walk 0.01 deg/s/sqrt(Hz) * sqrt(1200 s) = 0.35 deg, and a bias of 4.6
    deg/h held for 1200 s = 1.5 deg; fails if either is off by an order of magnitude."""
    spec = COMPASSES["mpu9250"]
    ends = [GyroCompass(spec, dt=0.1, seed=s).errors(12_000)[-1] for s in range(60)]
    spread = math.degrees(float(np.std(ends)))
    walk = spec.noise_density * math.sqrt(1200)
    bias = spec.bias_instability / 3600 * 1200
    assert 0.5 * math.hypot(walk, bias) < spread < 2.0 * (walk + bias)


def test_the_ideal_compass_is_the_truth_and_a_reading_turns_the_heading():
    assert not GyroCompass.part("ideal", dt=0.1, seed=0).errors(100).any()
    headings = np.array([[1.0, 0.0], [0.0, 1.0]])
    turned = reading(headings, np.array([math.pi / 2, math.pi / 2]))
    assert np.allclose(turned, [[0.0, 1.0], [-1.0, 0.0]], atol=1e-6)
    with pytest.raises(ValueError, match="unknown compass 'x'"):
        GyroCompass.part("x", dt=0.1, seed=0)
    with pytest.raises(ValueError, match="dt must be a positive"):
        GyroCompass(COMPASSES["mpu9250"], dt=0.0, seed=0)
