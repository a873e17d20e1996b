"""Tests of robopuppet.puppet_sim.puppet_publishers without a ROS master: a Step as messages."""
import rospy

from robopuppet import settings
from robopuppet.puppet_sim.puppet_device import Step
from robopuppet.puppet_sim.puppet_model import ControlTick
from robopuppet.puppet_sim.puppet_publishers import StepPublishers

STAMP = rospy.Time(7, 250000000)


class Recorder:
    """A publisher that keeps what it is given."""

    def __init__(self):
        self.messages = []

    def publish(self, msg):
        self.messages.append(msg)


def publishers(monkeypatch):
    monkeypatch.setattr(rospy.Time, 'now', staticmethod(lambda: STAMP))
    pubs = StepPublishers.__new__(StepPublishers)
    pubs.config, pubs.opmode, pubs.control, pubs.hand_torque = (Recorder() for _ in range(4))
    return pubs


def test_a_step_with_everything_publishes_each_message_once_per_item(monkeypatch):
    pubs = publishers(monkeypatch)
    n = settings.NUM_JOINTS
    config = tuple(float(i) for i in range(n * len(settings.NAMES)))
    ticks = [ControlTick(1.0, (0.1,) * n, (0.2,) * n, (0.3,) * n),
             ControlTick(1.02, (0.4,) * n, (0.5,) * n, (0.6,) * n)]
    pubs.publish(Step(config, 'hold', ticks, None, [], (0.7,) * n))
    (grid,) = pubs.config.messages
    assert tuple(grid.data) == config
    assert [(d.label, d.size, d.stride) for d in grid.layout.dim] == [
        ('joint', n, n * len(settings.NAMES)), ('setting', len(settings.NAMES),
                                                len(settings.NAMES))]
    assert [m.data for m in pubs.opmode.messages] == ['hold']
    first, second = pubs.control.messages
    assert first.name == list(settings.JOINT_NAMES) and first.header.stamp == STAMP
    assert (first.position, first.velocity, first.effort) == ([0.1] * n, [0.2] * n, [0.3] * n)
    assert second.position == [0.4] * n
    (torque,) = pubs.hand_torque.messages
    assert torque.effort == [0.7] * n and torque.position == [] and torque.header.stamp == STAMP


def test_a_step_with_nothing_publishes_nothing(monkeypatch):
    pubs = publishers(monkeypatch)
    pubs.publish(Step(None, None, [], None, [], None))
    assert not any(p.messages for p in (pubs.config, pubs.opmode, pubs.control, pubs.hand_torque))
