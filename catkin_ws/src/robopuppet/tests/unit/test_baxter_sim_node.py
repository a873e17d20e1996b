"""Tests of robopuppet.baxter_sim.baxter_sim_node without a ROS master: parameter checks, refusal logs,
the publishing loop's survival."""
import math
import threading
import time

import pytest
import rospy
from baxter_core_msgs.msg import JointCommand

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim import baxter_sim_node
from robopuppet.baxter_sim.baxter_model import BaxterModel
from robopuppet.baxter_sim.baxter_refusals import RefusalThrottle
from robopuppet.baxter_sim.baxter_sim_node import BaxterSimNode, positive_param
from robopuppet.periodic import Guard, Loop


@pytest.mark.parametrize('value, expected', [(100, 100.0), (0.2, 0.2), ('0.5', 0.5)])
def test_positive_param_accepts_positive_numbers(value, expected):
    assert positive_param('/baxter_sim/rate_hz', value) == expected


@pytest.mark.parametrize('value', [0, -1.0, 'fast', None, math.nan, math.inf, True, [1.0]])
def test_positive_param_names_the_parameter_when_refusing(value):
    with pytest.raises(ValueError, match='/baxter_sim/rate_hz'):
        positive_param('/baxter_sim/rate_hz', value)


@pytest.fixture(name='node')
def fixture_node(monkeypatch):
    """The node's command handlers around an enabled model, without a ROS master."""
    node = BaxterSimNode.__new__(BaxterSimNode)
    node._lock = threading.Lock()
    node._throttle = RefusalThrottle(baxter_sim_node.WARN_INTERVAL_S)
    node._model = BaxterModel(bd.load(), 0.0)
    node._model.set_enabled(True)
    node.warnings = []
    clock = {'now': 100.0}
    node.clock = clock
    monkeypatch.setattr(rospy, 'logwarn', lambda text, *args: node.warnings.append(text % args))
    monkeypatch.setattr(rospy, 'get_time', lambda: clock['now'])
    monkeypatch.setattr(baxter_sim_node.time, 'monotonic', lambda: clock['now'])
    return node


def joint_command(node, side, mode, names, values):
    node._on_joint_command(JointCommand(mode=mode, names=names, command=values),
                           '/robot/limb/%s/joint_command' % side, side)


def test_refusals_of_different_kinds_and_sides_are_each_logged(node):
    # Before: all joint-command refusals shared one throttle slot, so only the first was logged.
    joint_command(node, 'left', JointCommand.VELOCITY_MODE, ['left_s0'], [0.1])
    node.clock['now'] += 0.5
    joint_command(node, 'right', JointCommand.TORQUE_MODE, ['right_s0'], [0.1])
    node.clock['now'] += 0.5
    joint_command(node, 'left', JointCommand.POSITION_MODE, ['right_s0'], [0.1])
    node.clock['now'] += 0.5
    joint_command(node, 'left', JointCommand.TORQUE_MODE, ['left_s0'], [0.1])
    assert len(node.warnings) == 4, node.warnings
    for words in (('left', 'mode 2'), ('right', 'mode 3'), ('left', 'right_s0'),
                  ('left', 'mode 3')):
        assert any(all(w in line for w in words) for line in node.warnings), words


def test_repeats_of_one_refusal_are_throttled_and_counted(node):
    for _ in range(150):
        joint_command(node, 'left', JointCommand.VELOCITY_MODE, ['left_s0'], [0.1])
        node.clock['now'] += 0.01
    assert len(node.warnings) == 1
    node.clock['now'] += 1.0
    joint_command(node, 'left', JointCommand.VELOCITY_MODE, ['left_s0'], [0.1])
    assert len(node.warnings) == 2
    assert '149 more since the last line' in node.warnings[1]


def test_a_deeply_nested_gripper_args_is_refused_with_a_log_line(node):
    # Before: RecursionError escaped the callback as a traceback.
    msg_args = '{"position": ' + '[' * 4000   # within the length limit, deeper than Python's
    node._on_gripper_command(
        baxter_sim_node.EndEffectorCommand(id=baxter_sim_node.GRIPPER_ID, command='go',
                                           args=msg_args, sender='fuzz', sequence=1),
        '/robot/end_effector/left_gripper/command', 'left')
    assert len(node.warnings) == 1
    assert 'nested too deeply' in node.warnings[0] and len(node.warnings[0]) < 400


def test_the_publishing_loop_survives_an_exception_and_logs_the_count(node, monkeypatch):
    errors, cycles = [], []
    monkeypatch.setattr(rospy, 'logerr', lambda text, *args: errors.append(text % args))
    monkeypatch.setattr(rospy, 'get_rostime', lambda: rospy.Time(1, 0))
    node._guard = Guard('/baxter_sim', node._log_failure)
    node._cycle = 0
    node._publish_state = lambda: None

    def publish_cycle(stamp):
        cycles.append(stamp)
        if len(cycles) <= 2:
            raise OverflowError('a value too large for the message')
    node._publish_cycle = publish_cycle
    loop = Loop(node._guard, 'publishing loop', 0.005, node._loop_once).start()
    deadline = time.monotonic() + 10.0
    while len(cycles) < 10 and time.monotonic() < deadline:
        time.sleep(0.01)
    loop.stop()
    assert len(cycles) >= 10                  # it kept running after the exceptions
    assert node._guard.errors == 2
    assert len(errors) == 1                   # the second one within 5 s is counted, not logged
    assert 'OverflowError' in errors[0] and '[1 failures in all since start]' in errors[0]
