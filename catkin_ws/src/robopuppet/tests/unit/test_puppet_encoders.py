"""Unit tests of robopuppet.puppet_sim.puppet_encoders: raw angles in counts, statuses, index."""
import math

import pytest

from robopuppet.protocol import codec
from robopuppet.puppet_sim.puppet_encoders import HALL_RAD_PER_COUNT, QUAD_RAD_PER_COUNT, Encoders
from robopuppet.settings import QUAD_JOINTS

POSE = (0.3, 0.5, -0.25, 0.9, 0.2, 0.4, -0.15)


def test_hall_encoders_read_the_mechanical_angle_in_whole_counts():
    encoders = Encoders(POSE)
    raw = encoders.raw_rad(1, 0.5)
    assert raw == pytest.approx(0.5, abs=HALL_RAD_PER_COUNT / 2)
    assert raw / HALL_RAD_PER_COUNT == pytest.approx(round(raw / HALL_RAD_PER_COUNT))
    assert encoders.raw_rad(3, -0.1) == pytest.approx(2 * math.pi - 0.1,
                                                      abs=HALL_RAD_PER_COUNT)  # 0..2 pi
    assert [encoders.status(j) for j in (1, 3, 5)] == [codec.WORKING] * 3


def test_a_missing_hall_encoder_is_disconnected_and_has_no_angle():
    encoders = Encoders(POSE, hall_disconnected=[5])
    assert encoders.status(5) == codec.DISCONNECTED and encoders.raw_rad(5, 0.4) is None
    with pytest.raises(ValueError, match='only hall-encoder joints'):
        Encoders(POSE, hall_disconnected=[0])


def test_quadrature_encoders_count_from_power_on_until_their_index_mark():
    encoders = Encoders(POSE)
    assert [encoders.status(j) for j in QUAD_JOINTS] == [codec.UNCALIBRATED] * 4
    assert encoders.raw_rad(0, 0.5) == pytest.approx(0.2, abs=QUAD_RAD_PER_COUNT)
    before, after = list(POSE), list(POSE)
    after[0] = -0.1                      # joint 0 passes 0
    after[2] = -0.2                      # joint 2 moves, but not through its mark
    encoders.move(before, after)
    assert encoders.status(0) == codec.WORKING and encoders.status(2) == codec.UNCALIBRATED
    assert encoders.raw_rad(0, -0.1) == pytest.approx(-0.1, abs=QUAD_RAD_PER_COUNT)
    assert encoders.raw_rad(2, -0.2) == pytest.approx(0.05, abs=QUAD_RAD_PER_COUNT)


def test_landing_on_the_index_pulse_calibrates():
    encoders = Encoders(POSE)
    before, after = list(POSE), list(POSE)
    before[4], after[4] = 0.2, 0.004
    encoders.move(before, after)
    assert encoders.status(4) == codec.WORKING
