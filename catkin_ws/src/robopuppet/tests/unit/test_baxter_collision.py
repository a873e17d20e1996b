"""Tests of robopuppet.baxter_sim.baxter_collision through BaxterApi: the suppress topics'
timeout, zero-g from a cuff squeeze and its suppression, the collision avoidance state and the
log lines of each change, without ROS."""

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim import baxter_api as api
from robopuppet.baxter_sim.baxter_collision import SUPPRESS_TIMEOUT_S, Suppression
from robopuppet.baxter_sim.baxter_model import BaxterModel

COMMAND = '/robot/limb/left/joint_command'
SQUEEZE = '/baxter_sim/digital_input'
POSITION = 1
DT = 0.01
TARGET = {'left_s0': 0.6, 'left_e1': 1.5}


class Robot:
    """A BaxterApi stepped at 100 Hz, the left arm commanded toward TARGET at 50 Hz."""

    def __init__(self):
        self.sim = api.BaxterApi(BaxterModel(bd.load(), 0.0), 0.2)
        self.sim.set_enabled('/robot/set_super_enable', True, 0.0)
        self.t, self.notes, self.warnings = 0.0, [], []

    def run(self, seconds, command=True, suppress=(), every=2):
        """Step for `seconds`: every other step send a command (its refusal lines are kept),
        every `every` steps the suppress messages (side, method)."""
        for i in range(int(round(seconds / DT))):
            self.t += DT
            if i % every == 0:
                for side, method in suppress:
                    getattr(self.sim, method)('/suppress', side, self.t, self.t)
            if i % 2 == 0:
                if command:
                    reply = self.sim.joint_command(COMMAND, 'left', POSITION, list(TARGET),
                                                   list(TARGET.values()), self.t, self.t)
                    self.warnings += [reply.warning] if reply.warning else []
            self.notes += self.sim.cycle(self.t).notes

    def squeeze(self, pressed):
        assert self.sim.digital_input(SQUEEZE, 'left_lower_cuff', pressed, self.t).warning is None

    def left(self):
        return dict(self.sim.model.arms['left'].positions)


CUFF = (('left', 'suppress_cuff_interaction'),)
ZERO_G = 'left arm: zero-g: cuff squeezed; the arm holds and joint commands are refused'
ZERO_G_ENDED = 'left arm: zero-g ended: joint commands are obeyed again'
CUFF_SUPPRESSED = 'left arm: cuff interaction suppressed: a squeeze does not give zero-g'
CUFF_LAPSED = 'left arm: cuff interaction suppression lapsed (no message for 0.2 s)'


def test_one_message_suppresses_for_the_timeout_only():
    suppression = Suppression()
    assert not suppression.active(0.0)
    suppression.message(1.0)
    assert suppression.active(1.0) and suppression.active(1.0 + SUPPRESS_TIMEOUT_S)
    assert not suppression.active(1.0 + SUPPRESS_TIMEOUT_S + 0.01)
    suppression.message(0.5)     # a late message never shortens it
    assert suppression.active(1.1)


def test_a_cuff_squeeze_gives_zero_g_the_arm_holds_and_commands_are_refused():
    robot = Robot()
    robot.run(0.3)
    before = robot.left()
    assert before['left_s0'] > 0.05 and not robot.warnings     # it was moving toward TARGET
    robot.squeeze(True)
    robot.run(1.0)
    held = robot.left()
    assert held == before              # commands came every 20 ms: none moved it
    assert len(robot.warnings) == 1    # throttled: one line per 2 s
    assert 'zero-g' in robot.warnings[0] and COMMAND in robot.warnings[0]
    assert robot.notes == [ZERO_G]     # once, not every cycle
    robot.squeeze(False)
    robot.run(1.0)
    assert robot.left()['left_s0'] > held['left_s0'] + 0.2      # obeyed again
    assert robot.notes == [ZERO_G, ZERO_G_ENDED] and len(robot.warnings) == 1


def test_suppressed_cuff_interaction_keeps_the_arm_under_command_until_it_lapses():
    robot = Robot()
    robot.squeeze(True)
    robot.run(0.5, suppress=CUFF)                  # 50 Hz: never lapses
    assert robot.left()['left_s0'] > 0.1 and not robot.warnings
    assert robot.notes == [CUFF_SUPPRESSED]
    robot.run(0.5, command=False)                  # no more messages: zero-g after 0.2 s
    assert robot.notes == [CUFF_SUPPRESSED, CUFF_LAPSED, ZERO_G]
    held = robot.left()
    robot.run(0.5)
    assert robot.left() == held
    assert robot.warnings and 'zero-g' in robot.warnings[0]
    robot.run(0.5, suppress=CUFF)                  # suppressed again: commands obeyed
    assert robot.notes[-2:] == [CUFF_SUPPRESSED, ZERO_G_ENDED]     # the cause, then its effect
    assert robot.left()['left_s0'] > held['left_s0'] + 0.1


def test_suppress_messages_slower_than_5_hz_do_not_keep_the_cuff_suppressed():
    robot = Robot()
    robot.squeeze(True)
    robot.run(1.0, suppress=CUFF, every=25)        # 4 Hz: lapses between messages
    assert robot.notes[:3] == [CUFF_SUPPRESSED, CUFF_LAPSED, ZERO_G]
    assert robot.warnings


def test_no_zero_g_while_disabled_nor_for_the_other_arm():
    robot = Robot()
    robot.squeeze(True)
    robot.run(0.02, command=False)
    assert robot.notes == [ZERO_G]
    reply = robot.sim.joint_command('/robot/limb/right/joint_command', 'right', POSITION,
                                    ['right_s0'], [-0.5], robot.t, robot.t)
    assert reply.warning is None
    robot.sim.set_enabled('/robot/set_super_enable', False, robot.t)
    robot.run(0.1, command=False)
    assert robot.notes == [ZERO_G, ZERO_G_ENDED]
    robot.sim.set_enabled('/robot/set_super_enable', True, robot.t)
    robot.run(0.1, command=False)
    assert robot.notes == [ZERO_G, ZERO_G_ENDED, ZERO_G]


def test_collision_avoidance_is_published_empty_and_its_suppression_logged():
    robot = Robot()
    robot.run(0.4, suppress=(('left', 'suppress_collision_avoidance'),))
    assert not robot.warnings
    cycle = robot.sim.cycle(robot.t + DT)
    for side in ('left', 'right'):
        assert cycle.io['/robot/limb/%s/collision_avoidance_state' % side] == dict(
            other_arm=False, collision_object=[])
    assert robot.notes == ['left arm: collision avoidance suppressed (the stand-in models no '
                           'self-collision: nothing to avoid either way)']
    robot.run(0.3, command=False)
    assert robot.notes[-1] == ('left arm: collision avoidance suppression lapsed (no message '
                               'for 0.2 s)')
    assert robot.left()['left_s0'] > 0.1     # suppressed or not, commands were obeyed
