"""robopuppet.arm.command_loop: where each of the controller's actions goes, and how a step fails
(rospy's publishers replaced by recorders; no ROS master)."""
import threading

import pytest
import rospy
from baxter_core_msgs.msg import JointCommand

from robopuppet import interface
from robopuppet.arm import baxter_upkeep, command_loop, controller, opmode
from robopuppet.periodic import Guard
from ros_stand_ins import Publisher, record_publishers

PERIOD_S = 0.01


class Core:
    """A stand-in for controller.ArmController: steps return `actions`; records the calls."""

    def __init__(self, actions=(), why=''):
        self.actions, self.why, self.calls = list(actions), why, []

    def step(self, now):
        self.calls.append('step')
        return self.actions

    def done(self, now):
        self.calls.append('done')

    def failed(self, error):
        self.calls.append('failed: %s' % error)

    def stall(self, now):
        return self.why


def loop(monkeypatch, core, reports=None, lock=None):
    record_publishers(monkeypatch)
    reports = [] if reports is None else reports
    return command_loop.CommandLoop('R', core, lock or threading.Lock(), Guard('arm_R', print),
                                    PERIOD_S, reports.append, 'arm_R')


def test_each_action_goes_out_on_its_topic(monkeypatch):
    names = ['right_s0'] * 7
    report = controller.Report(*([None] * len(controller.Report._fields)))
    reports = []
    steps = loop(monkeypatch, Core([
        controller.Enable(), controller.ArmCommand('right', names, [0.1] * 7),
        opmode.SetSetpoints([0.2] * 7), opmode.SetOpmode(interface.HOLD),
        baxter_upkeep.GripperCommand('left', 65538, 'go', '{}', 4), report]), reports)
    steps.step(1.0)
    topics = [topic for topic, _ in Publisher.sent]
    assert topics == [interface.SET_SUPER_ENABLE, interface.limb_topic('right', 'joint_command')] \
        + [interface.joint_topic('R', j, 'setpoint') for j in range(7)] \
        + [interface.puppet_ns('R') + '/' + interface.OPMODE,
           interface.baxter_gripper_topic('left', 'command')]
    msgs = [msg for _, msg in Publisher.sent]
    assert msgs[0].data is True
    assert (msgs[1].mode, list(msgs[1].command), msgs[1].names) == (
        JointCommand.POSITION_MODE, [0.1] * 7, names)
    assert [m.data for m in msgs[2:9]] == [pytest.approx(0.2)] * 7 and msgs[9].data == 'hold'
    assert (msgs[10].id, msgs[10].command, msgs[10].sequence) == (65538, 'go', 4)
    assert reports == [report]


def test_a_step_that_fails_to_go_out_is_raised_and_faults_the_next_not_done(monkeypatch):
    core = Core([controller.Enable(), 'no action'])
    steps = loop(monkeypatch, core)
    with pytest.raises(KeyError):
        steps.step(1.0)
    assert core.calls == ['step', "failed: <class 'str'>"]
    core.actions = [controller.Enable()]
    steps.step(1.1)
    assert core.calls[-2:] == ['step', 'done']


def test_the_watchdog_steps_a_stalled_loop_and_says_so_while_the_lock_is_held(monkeypatch):
    logged = []
    monkeypatch.setattr(rospy, 'logerr_throttle', lambda period, *args: logged.append(args))
    core, lock = Core(why='no step completed for 0.11 s'), threading.Lock()
    steps = loop(monkeypatch, core, lock=lock)
    with lock:   # stuck: after STALL_PERIODS command periods the watchdog gives up, no step
        steps._watch()
    assert core.calls == [] and 'holds its lock for over 0.10 s' in logged[0][0] % logged[0][1:]
    steps._watch()
    assert core.calls == ['step', 'done'] and 'command loop failed' in logged[1][0]
    core.why = ''
    steps._watch()
    assert core.calls == ['step', 'done']   # not stalled: nothing to do
