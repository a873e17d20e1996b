"""Tests of robopuppet.assist.assist_node without a ROS master: waiting for the model file, a
file that is no model, garbage on every subscribed topic, and what goes out on which topic."""
import collections
import math

import pytest
import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import String

import ros_stand_ins
from robopuppet import interface as ifc
from robopuppet.assist import assist_core, assist_node, model_file
from robopuppet.baxter_description import arm_joint_names
from robopuppet_msgs.msg import TeleopState

Prediction = collections.namedtuple('Prediction', 'positions gripper_closed confidence familiar')
LEADER_NAMES = arm_joint_names('right')


class Predictor:
    """A stand-in of model_file's Predictor: the follower mirrors the leader, always familiar."""
    leader, follower, task, method = 'right', 'left', 'carry the tray', 'lwr'

    def reset(self):
        pass

    def step(self, t, leader_positions):
        return Prediction([-a for a in leader_positions], False, 0.8, True)


class Clock:
    """time.monotonic of the node, moved on by hand."""
    t = 100.0

    def __call__(self):
        return self.t


class StubLoop:
    """A Loop that never runs on its own: the test calls the node's methods."""
    def __init__(self, guard, what, period_s, function):
        self.stopped = False

    def start(self):
        return self

    def stop(self, timeout_s=1.0):
        self.stopped = True


@pytest.fixture(name='node')
def fixture_node(monkeypatch, tmp_path):
    ros_stand_ins.record_publishers(monkeypatch)
    subscribers = {}
    monkeypatch.setattr(rospy, 'Subscriber', lambda topic, kind, callback, args, **kw:
                        subscribers.__setitem__(topic, lambda msg: callback(msg, args)))
    model = tmp_path / 'tray.npz'
    monkeypatch.setattr(rospy, 'get_param', lambda name, default=None: {
        '~model': str(model)}.get(name, default))
    monkeypatch.setattr(rospy, 'get_name', lambda: '/assist')
    monkeypatch.setattr(rospy, 'on_shutdown', lambda hook: None)
    monkeypatch.setattr(rospy.Time, 'now', staticmethod(lambda: rospy.Time(50)))
    monkeypatch.setattr(assist_node, 'Loop', StubLoop)
    clock = Clock()
    monkeypatch.setattr(assist_node.time, 'monotonic', clock)
    logs = []
    for level in ('logwarn', 'loginfo', 'logerr'):
        monkeypatch.setattr(rospy, level, lambda text, *args, level=level: logs.append(
            (level, text % args)))
    monkeypatch.setattr(rospy, 'logwarn_throttle', lambda period, text, *args: logs.append(
        ('logwarn', text % args)))
    node = assist_node.AssistNode()
    node.test = collections.namedtuple('Test', 'model subscribers clock logs')(
        model, subscribers, clock, logs)
    return node


def load_stand_in(monkeypatch, node):
    """Make the model file a valid one (load gives the stand-in) and load it."""
    node.test.model.write_bytes(b'a model')
    monkeypatch.setattr(model_file, 'load', lambda path: Predictor())
    node._check_model()


def joint_states(positions, names=LEADER_NAMES, stamp=7):
    return JointState(header=rospy.Header(stamp=rospy.Time(stamp)), name=list(names),
                      position=list(positions))


def run(node, seconds, positions=(0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7)):
    for _ in range(int(round(seconds * 100))):
        node.test.clock.t += 0.01
        node.test.subscribers[ifc.ROBOT_JOINT_STATES](joint_states(positions))
        node._step()


def test_a_missing_model_file_is_waited_for_and_said_once(node):
    node._check_model()
    node._check_model()
    node._step()
    waiting = ('waiting for the model file %s: record demonstrations and run train_assist '
               '(docs/assist.md)' % node.test.model)
    assert node.test.logs == [('loginfo', '/assist: ' + waiting)]
    state, = ros_stand_ins.sent_on(ifc.ASSIST_STATE)
    assert state.state == 'off' and state.detail == 'assist off: ' + waiting
    assert not node._model_loop.stopped


def test_a_file_that_is_no_model_turns_it_off_and_a_new_file_is_tried(node, monkeypatch):
    node.test.model.write_bytes(b'not a model')
    node._check_model()
    node._check_model()  # the same file: not read again, not said again
    node._step()
    errors = [text for level, text in node.test.logs if level == 'logerr']
    assert len(errors) == 1 and 'cannot use the model' in errors[0]
    state = ros_stand_ins.sent_on(ifc.ASSIST_STATE)[-1]
    assert state.state == 'off' and 'not an assist model file' in state.detail
    load_stand_in(monkeypatch, node)
    assert node._model_loop.stopped
    run(node, 0.5)
    assert ros_stand_ins.sent_on(ifc.ASSIST_STATE)[-1].state == 'ready'


def test_it_publishes_the_target_and_both_ghost_arms_on_the_models_sides(node, monkeypatch):
    load_stand_in(monkeypatch, node)
    run(node, 0.5)
    target = ros_stand_ins.sent_on('/puppet/arm_R/assist_target')[-1]
    assert target.side == 'left' and not target.hold and target.header.stamp == rospy.Time(7)
    assert list(target.position) == pytest.approx([-0.1, -0.2, -0.3, -0.4, -0.5, -0.6, -0.7])
    ghost = ros_stand_ins.sent_on('/puppet/arm_L/assist_prediction')[-1]
    assert list(ghost.name) == arm_joint_names('left') and ghost.position == target.position
    leader = ros_stand_ins.sent_on('/puppet/arm_R/assist_prediction')[-1]
    assert list(leader.name) == LEADER_NAMES and leader.position[0] == pytest.approx(0.1)
    state = ros_stand_ins.sent_on(ifc.ASSIST_STATE)[-1]
    assert (state.state, state.leader, state.follower, state.method) == (
        'ready', 'right', 'left', 'lwr')
    assert len(ros_stand_ins.sent_on(ifc.ASSIST_STATE)) < 10  # not every step


@pytest.mark.parametrize('garbage', [
    joint_states([0.1] * 6),                                   # wrong length
    joint_states([math.nan] * 7),                              # NaN
    joint_states([0.1] * 7, names=arm_joint_names('left')),    # not the leader's names
    joint_states([0.1] * 7, names=['x%d' % i for i in range(7)])])
def test_garbage_joint_states_are_ignored_with_a_warning(node, monkeypatch, garbage):
    load_stand_in(monkeypatch, node)
    run(node, 0.5)
    for _ in range(20):
        node.test.clock.t += 0.01
        node.test.subscribers[ifc.ROBOT_JOINT_STATES](garbage)
        node._step()
    warnings = [text for level, text in node.test.logs if level == 'logwarn']
    assert warnings and all('ignored' in w or 'refused' in w for w in warnings)
    target = ros_stand_ins.sent_on('/puppet/arm_R/assist_target')[-1]
    assert target.hold and target.position[0] == pytest.approx(-0.1)  # its pose went stale
    run(node, 0.5)  # the node keeps running
    assert not ros_stand_ins.sent_on('/puppet/arm_R/assist_target')[-1].hold


def test_commands_stop_and_start_and_garbage_is_said(node, monkeypatch):
    load_stand_in(monkeypatch, node)
    run(node, 0.5)
    node.test.subscribers[ifc.ASSIST_COMMAND](String('explode'))
    assert ('logwarn', "/assist: assist command 'explode' ignored: not one of stop, start") \
        in node.test.logs
    node.test.subscribers[ifc.ASSIST_COMMAND](String('stop'))
    run(node, 0.05)
    assert ros_stand_ins.sent_on(ifc.ASSIST_STATE)[-1].state == 'stopped'
    assert ros_stand_ins.sent_on('/puppet/arm_R/assist_target')[-1].hold
    node.test.subscribers[ifc.ASSIST_COMMAND](String('start'))
    run(node, 0.05)
    assert ros_stand_ins.sent_on(ifc.ASSIST_STATE)[-1].state == 'ready'


def test_the_leaders_teleop_state_makes_it_assisting(node, monkeypatch):
    load_stand_in(monkeypatch, node)
    run(node, 0.5)
    node.test.subscribers['/puppet/arm_R/teleop_state'](TeleopState(assist_left=True))
    run(node, 0.05)
    state = ros_stand_ins.sent_on(ifc.ASSIST_STATE)[-1]
    assert state.state == assist_core.ASSISTING and 'press 2 on puppet L' in state.detail
