"""arm_X's decisions (robopuppet.arm.controller): steps, actions, report, the command loop's
health; fed as the node feeds it, with time passed in. The operator host's clock runs
OPERATOR_OFFSET_S ahead of the robot's, and answers the controller's pings (see Rig)."""
import collections

import pytest

from robopuppet import baxter_description, interface, settings
from robopuppet.arm import baxter_upkeep, baxter_watch, controller, opmode, timing
from robopuppet.periodic import Guard

LIMITS = {side: baxter_description.arm_limits(side) for side in interface.BAXTER_SIDES}
PERIOD_S = 0.01
ROBOT_CLOCK_S = 1000.0       # the robot host's ROS clock at t = 0
OPERATOR_OFFSET_S = 37.5     # the operator host's clock minus the robot host's
POSE = {side: [baxter_description.NEUTRAL_POSE[s] for s in baxter_description.ARM_JOINT_SUFFIXES]
        for side in interface.BAXTER_SIDES}


class Rig:
    """An ArmController of puppet R with a clock; Baxter and the puppet report as asked."""

    def __init__(self, comm_rate_hz=10.0, side='R', echo=True, zone_guards=None):
        self.guard = Guard('arm_' + side, lambda text: None)
        self.core = controller.ArmController(
            side, LIMITS, timing.state_timeout(comm_rate_hz), interface.HEARTBEAT_TIMEOUT_S,
            0.5, PERIOD_S, self.guard, 0.0,
            timing.sample_age_bound(timing.DEFAULT_MAX_SAMPLE_AGE_S), zone_guards)
        self.t = 0.0
        self.echo = echo   # the operator host answers pings at once (2 ms each way)
        self.enabled = True
        self.echo_t = None   # when the newest echo came
        self.robot_age_s = 0.0   # how old Baxter's joint states are by their stamp on arrival
        self.robot_sides = interface.BAXTER_SIDES   # the arms in Baxter's joint states

    def now_s(self):
        """Return the robot host's ROS clock (s)."""
        return ROBOT_CLOCK_S + self.t

    def operator_s(self, ago_s=0.0):
        """Return the operator host's clock (s) ago_s seconds ago."""
        return self.now_s() - ago_s + OPERATOR_OFFSET_S

    def link(self):
        """Send a ping if one is due; the operator host answers it when echo is on."""
        ping = self.core.ping(self.now_s())
        if ping and self.echo:
            seq, sent_s = ping
            assert self.core.on_echo(sent_s + 0.004, seq, sent_s,
                                     sent_s + 0.002 + OPERATOR_OFFSET_S) == ''
            self.echo_t = self.t

    def baxter(self, enabled=True):
        self.core.on_robot_state(self.t, enabled and self.enabled, False, False)
        names = sum((baxter_description.arm_joint_names(s) for s in self.robot_sides), [])
        self.core.on_robot_joints(self.t, names, sum((POSE[s] for s in self.robot_sides), []),
                                  [], self.robot_age_s)

    def puppet(self, statuses=interface.WORKING, angles=None, age_s=0.0):
        """Send the puppet's joint states, age_s old on arrival."""
        for joint in settings.JOINTS:
            self.core.on_status(joint, statuses)
        self.core.on_heartbeat(self.t)
        return self.core.on_joint_states(self.t, settings.JOINT_NAMES, angles or POSE['right'],
                                         self.operator_s(age_s), self.now_s())

    def step(self, dt=PERIOD_S, puppet=True, angles=None, age_s=0.0):
        self.t += dt
        self.baxter()
        self.link()
        if puppet:
            self.puppet(angles=angles, age_s=age_s)
        out = self.core.step(self.t)
        self.core.done(self.t)
        return out

    def press(self, button):
        self.core.on_button(button)
        out = self.step()
        self.core.on_button(0)
        return out


def report_in(actions):
    """Return the Report among a step's actions (it comes last), or None."""
    reports = [a for a in actions if isinstance(a, controller.Report)]
    assert reports in ([], actions[-1:])
    return reports[0] if reports else None


def ready():
    rig = Rig()
    rig.step()
    assert rig.core.teleop.state == interface.READY
    return rig


def test_the_diagnostics_status_is_found_by_the_puppets_namespace_and_what_it_is_about():
    report = report_in(Rig(side='L').step())
    assert report.hardware_id == interface.puppet_ns('L')
    assert report.diag_name.endswith(interface.DIAG_TELEOP)
    assert report.diag_name.startswith('arm_L')


def test_the_report_goes_out_on_every_change_and_at_least_every_half_second():
    rig = ready()
    reports = [(rig.t, report_in(rig.step())) for _ in range(120)]
    times = [t for t, report in reports if report]
    assert len(times) == 2 and times[1] - times[0] == pytest.approx(0.5, abs=PERIOD_S + 1e-9)
    assert not any(report.changed for _, report in reports if report)
    changed = report_in(rig.press(interface.BUTTON_RIGHT))
    assert changed.changed and changed.state == interface.FOLLOWING and changed.follow_right
    assert dict(changed.values)['follow_right'] == 'True'


class Wall:
    """A stand-in for world.zones.ZoneGuard: while `blocking`, every motion is cut at its start
    by zone 'bed' at link right_hand."""

    def __init__(self):
        self.blocking = False

    def limit_box(self, lo, hi, before, command):
        if self.blocking:
            return list(before), collections.namedtuple('Hit', 'zone link')('bed', 'right_hand')
        return command, None


def test_the_report_names_the_zone_that_holds_an_arm_back_and_changes_with_it():
    wall = Wall()
    rig = Rig(zone_guards={'right': wall})
    rig.step()
    rig.press(interface.BUTTON_RIGHT)
    report = report_in(rig.step(0.5))
    assert (report.zone_left, report.zone_right) == ('', '')
    wall.blocking = True
    held = report_in(rig.step())
    assert held.changed and (held.zone_left, held.zone_right) == ('', 'bed')
    assert held.detail == "held back by keep-out zone 'bed' (right_hand)"
    assert dict(held.values)['zone_right'] == 'bed'
    wall.blocking = False
    free = report_in(rig.step())
    assert free.changed and free.zone_right == ''
    assert free.detail == 'Baxter follows with its right arm'   # the zone no longer said
    wall.blocking = True
    rig.step()
    off = report_in(rig.press(interface.BUTTON_RIGHT))   # stops following: no arm held back
    assert off.zone_right == '' and 'keep-out' not in off.detail


@pytest.mark.parametrize('rate_hz, level, stop', [(10.0, 'OK', '0.50'), (2.0, 'WARN', '2.10')])
def test_the_stop_time_at_the_comm_rate_is_in_the_diagnostics_and_a_late_one_warns(
        rate_hz, level, stop):
    rig = Rig(comm_rate_hz=rate_hz)
    report = report_in(rig.step())
    assert report.state == interface.READY
    assert report.level == level
    values = dict(report.values)
    assert values['stop_within_s'] == stop and values['comm_rate_hz'] == '%g' % rate_hz
    assert ('only after %s s' % stop in report.message) == (level == 'WARN')


def test_a_fault_is_an_error_even_at_a_low_rate():
    rig = Rig(comm_rate_hz=2.0)
    rig.step()
    report = report_in(rig.step(3.0, puppet=False))
    assert report.state == interface.FAULT and report.level == 'ERROR'


def test_baxter_is_asked_to_enable_once_a_second_until_it_is_ready():
    rig = Rig()
    enables = []
    for _ in range(250):
        rig.t += PERIOD_S
        if rig.t > 2.0:
            rig.baxter()
        enables += [rig.t for a in rig.core.step(rig.t)
                    if isinstance(a, controller.Enable)]
    assert len(enables) == 2 and 1.0 <= enables[1] - enables[0] <= 1.0 + 2 * PERIOD_S
    assert rig.core.teleop.state == interface.CALIBRATING


def test_commands_name_baxters_joints_and_grips_carry_the_grippers_id():
    rig = ready()
    rig.core.on_gripper_state(rig.t, 'right', 65538, True)
    commands = [a for a in rig.press(interface.BUTTON_RIGHT)
                if isinstance(a, controller.ArmCommand)]
    assert [(a.side, a.names) for a in commands] == [
        ('right', baxter_description.arm_joint_names('right'))]
    rig.core.on_end_piece(0.0)  # the end-piece button pressed
    grips = [a for a in rig.step() if isinstance(a, baxter_upkeep.GripperCommand)]
    assert [(g.side, g.id, g.command) for g in grips] == [('right', 65538, 'go')]


def test_a_gripper_that_follows_the_puppet_closed_is_not_calibrated():
    rig = ready()
    rig.press(interface.BUTTON_RIGHT)
    rig.core.on_end_piece(0.0)
    rig.step()
    assert rig.core.on_gripper_state(rig.t, 'right', 65538, False) == []
    assert [a.side for a in rig.core.on_gripper_state(rig.t, 'left', 65539, False)] == ['left']


def test_an_unknown_encoder_status_is_not_working_and_is_reported_cut_short():
    rig = ready()
    rig.press(interface.BUTTON_RIGHT)
    rig.t += PERIOD_S
    rig.puppet(statuses='WORKING' + 'x' * 100000)   # every joint
    report = report_in(rig.step(puppet=False))
    assert report.state == interface.CALIBRATING
    assert "joints 0, 1, 2, 3, 4, 5, 6 'WORKING" in report.detail, report.detail
    assert len(report.detail) < 200


def test_refused_and_non_finite_joint_states_are_counted_and_explained():
    rig = ready()
    taken, problem = rig.core.on_joint_states(rig.t, ['joint_0'], [0.0], rig.operator_s(),
                                              rig.now_s())
    assert not taken and 'refused (1 so far)' in problem and 'joint_1' in problem
    angles = list(POSE['right'])
    angles[4] = float('nan')
    rig.t += PERIOD_S   # a new stamp: the same one again would be out of order
    taken, problem = rig.core.on_joint_states(rig.t, settings.JOINT_NAMES, angles,
                                              rig.operator_s(), rig.now_s())
    assert taken and 'non-finite joint_4' in problem
    assert dict(report_in(rig.step(0.5)).values)['refused_joint_states'] == '1'


def test_a_command_loop_that_completes_no_step_is_a_fault_with_the_last_error():
    rig = ready()
    rig.press(interface.BUTTON_RIGHT)
    rig.guard.call('command loop', lambda: 1 / 0)
    assert rig.core.stall(rig.t + 10 * PERIOD_S) == ''
    why = rig.core.stall(rig.t + 10 * PERIOD_S + 0.001)
    assert 'no step completed' in why and 'ZeroDivisionError' in why
    out = rig.step(0.011)
    assert rig.core.teleop.state == interface.FAULT and 'ZeroDivisionError' in report_in(out).detail
    assert [a.side for a in out if isinstance(a, controller.ArmCommand)] == ['right']
    assert dict(report_in(out).values)['callback_errors'] == '1'


def test_a_step_that_failed_to_go_out_faults_the_next_one():
    rig = ready()
    rig.press(interface.BUTTON_RIGHT)
    rig.core.failed(OverflowError('1e39 is no Float32'))
    rig.step()
    assert rig.core.teleop.state == interface.FAULT
    assert 'OverflowError' in rig.core.teleop.detail


def test_steps_for_the_steady_stream_are_due_about_once_a_command_period():
    rig = ready()
    assert not rig.core.step_due(rig.t + 0.8 * PERIOD_S)
    assert rig.core.step_due(rig.t + 0.9 * PERIOD_S)


def test_teleop_actions_pass_through_in_order():
    rig = ready()
    actions = [a for a in rig.press(interface.BUTTON_OPMODE)
               if not isinstance(a, controller.Report)]
    assert actions == [opmode.SetSetpoints(POSE['right']), opmode.SetOpmode(interface.HOLD)]


def test_garbage_joint_states_of_another_publisher_are_bad_stamps_and_the_real_ones_are_used():
    """topic_garbage: plausible joint_states stamped long ago (1..1e9 s) from another publisher
    between the real ones were logged as "out of order: stamped 1.7e9 s before one already
    used". They are refused as bad stamps (the operator's), and every real sample is used."""
    rig = ready()
    for stamp_s in (1.0, 5.0, 100.0, rig.operator_s() - 601.0):   # the robot clock: 1000 s
        rig.t += PERIOD_S
        taken, problem = rig.core.on_joint_states(rig.t, settings.JOINT_NAMES, POSE['right'],
                                                  stamp_s, rig.now_s())
        assert not taken and 'stamp so far' in problem and 'not a time a sample was' in problem
        rig.step()   # a real sample: used
        assert rig.core.link.since_usable_s(rig.now_s()) == 0.0
    assert dict(rig.core.link.refused) == {'stamp': 4}


def test_a_used_stamp_in_the_future_on_a_refined_estimate_is_forgotten_and_said():
    rig, names = Rig(echo=False), settings.JOINT_NAMES
    core = rig.core
    seq, sent_s = core.ping(rig.now_s())   # a slow first echo: the offset +- 0.25 s
    rig.t += 0.5
    assert core.on_echo(rig.now_s(), seq, sent_s, sent_s + 0.25 + OPERATOR_OFFSET_S) == ''
    taken, _ = core.on_joint_states(rig.t, names, POSE['right'], rig.operator_s(-0.24),
                                    rig.now_s())   # garbage stamped 0.24 s ahead: let through
    assert taken
    seq, sent_s = core.ping(rig.now_s())   # a fast one: the offset +- 2 ms
    rig.t += 0.004
    assert core.on_echo(rig.now_s(), seq, sent_s, sent_s + 0.002 + OPERATOR_OFFSET_S) == ''
    taken, problem = core.on_joint_states(rig.t, names, POSE['right'], rig.operator_s(0.01),
                                          rig.now_s())
    assert taken and 'lies in the future' in problem and 'forgotten (1 so far)' in problem


def feel_ready(robot_age_s=0.0):
    """Return a ready Rig whose puppet holds (arm_X's hold), Baxter's joint states robot_age_s
    old by their stamp from now on."""
    rig = ready()
    rig.press(interface.BUTTON_OPMODE)
    assert rig.core.teleop.opmode == interface.HOLD
    rig.robot_age_s = robot_age_s
    return rig


def opmodes_in(actions):
    return [a.mode for a in actions if isinstance(a, opmode.SetOpmode)]


@pytest.mark.parametrize('age_s, mode', [(0.01, interface.FEEL), (1.1, interface.LIMP)])
def test_feel_takes_baxters_pose_as_old_as_its_stamp_says(age_s, mode):
    """A Baxter pose stamped more than baxter_upkeep.ROBOT_TIMEOUT_S (1 s) before its arrival
    is not fresh: feel is refused (the puppet goes limp); one 10 ms old is fresh."""
    rig = feel_ready(age_s)
    actions = rig.press(interface.BUTTON_OPMODE)
    assert opmodes_in(actions) == [mode]
    assert rig.core.teleop.state == interface.READY   # Baxter's messages arrive: present
    if mode == interface.LIMP:
        assert "Baxter's right arm pose is 1.10 s old" in rig.core.teleop.detail


def test_baxters_stamps_falling_behind_in_feel_let_the_puppet_go_limp():
    rig = feel_ready()
    assert opmodes_in(rig.press(interface.BUTTON_OPMODE)) == [interface.FEEL]
    rig.robot_age_s = 0.9
    assert opmodes_in(rig.step()) == []
    rig.robot_age_s = 1.1   # e.g. Baxter's joint states queued up on the way
    assert opmodes_in(rig.step()) == [interface.LIMP]
    assert "feel ended, the puppet goes limp: Baxter's right arm pose is 1.10 s old" in \
        rig.core.teleop.detail


def test_a_baxter_stamp_ahead_of_the_clock_counts_as_measured_on_arrival():
    """A future stamp (Baxter's clock ahead of the robot host's) is age 0: the pose is fresh,
    and it grows old from its arrival like any other, not 5 s later."""
    rig = feel_ready(-5.0)
    assert opmodes_in(rig.press(interface.BUTTON_OPMODE)) == [interface.FEEL]
    assert rig.core.teleop.robot.pose_age('right', rig.t) == 0.0
    arrived_t = rig.t
    rig.robot_sides = ('left',)   # Baxter's joint states go on, without the right arm's
    while not opmodes_in(rig.step()):
        assert rig.t - arrived_t < 1.5, 'the right arm pose never grew old'
    assert rig.t - arrived_t == pytest.approx(baxter_upkeep.ROBOT_TIMEOUT_S, abs=2 * PERIOD_S)
    assert rig.core.teleop.opmode == interface.LIMP


def test_a_stop_on_an_old_baxter_pose_extrapolates_it_at_most_max_extrapolation():
    """Following stops on an old pose (0.5 s by its stamp): the stay command is the pose moved
    on by its velocity for baxter_watch.MAX_EXTRAPOLATION_S (0.05 s) only."""
    rig = ready()
    rig.press(interface.BUTTON_RIGHT)
    speeds = [0.2, 0.0, 0.0, -0.3, 0.0, 0.0, 0.0]   # rad/s
    names = sum((baxter_description.arm_joint_names(s) for s in interface.BAXTER_SIDES), [])
    rig.core.on_robot_joints(rig.t, names, POSE['left'] + POSE['right'], [0.0] * 7 + speeds,
                             0.5)
    rig.core.on_button(interface.BUTTON_RIGHT)   # stop following, Baxter still
    out = rig.core.step(rig.t)                                 # reporting nothing newer
    stay = [a.angles for a in out if isinstance(a, controller.ArmCommand)]
    assert stay == [pytest.approx([a + v * baxter_watch.MAX_EXTRAPOLATION_S
                                   for a, v in zip(POSE['right'], speeds)])]
