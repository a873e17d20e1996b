"""Unit tests of the replay core: schedule, speed factor, approach, grippers, stop rules,
keep-out zones."""
import math
import re
import types

import numpy as np
import pytest

from robopuppet import baxter_description
from robopuppet.episodes import replay
from robopuppet.world import arm_capsules, shapes, zones
from robopuppet.episodes.export import Samples
from robopuppet.interface import BAXTER_SIDES, BUTTON_OPMODE, BUTTON_RIGHT

LIMITS = {side: baxter_description.arm_limits(side) for side in BAXTER_SIDES}
PERIOD_S = 0.01
START = [0.1, -0.3, 0.2, 1.0, -0.1, 0.5, 0.0]


def ramp_path(duration_s=2.0, joint=3, rise_rad=0.4, t0=5.0):
    """A right-arm path from START, joint rising linearly by rise_rad, commands at 100 Hz."""
    times = t0 + np.arange(0.0, duration_s + 1e-9, 0.01)
    values = np.tile(START, (len(times), 1))
    values[:, joint] += rise_rad * (times - t0) / duration_s
    return {'right': Samples(times, values)}


def started(paths, grips=None, robot=START, speed=1.0, t=0.0, **kwargs):
    core = replay.Replay(paths, grips or {'right': []}, LIMITS, speed, PERIOD_S, **kwargs)
    core.on_robot_pose(t, {'right': list(robot)})
    return core, core.start(t)


def run(core, t0, t1, follow=True):
    """Step from t0 to t1 at PERIOD_S; the robot measures exactly what it was commanded when
    follow; return [(t, Step)]."""
    steps, t = [], t0
    while t < t1 - 1e-9:
        t += PERIOD_S
        step = core.step(t)
        steps.append((t, step))
        if follow and step.commands:
            core.on_robot_pose(t, step.commands)
    return steps


def test_the_speed_factor_scales_episode_time():
    for speed in (0.5, 1.0, 2.0):
        core, first = started(ramp_path(), speed=speed)
        steps = [(0.0, first)] + run(core, 0.0, 2.0 / speed + 0.5)
        play_t = [t for t, s in steps if s.phase == replay.APPROACH][-1]  # episode time 0
        at = [(t, s) for t, s in steps if abs(t - play_t - 0.5) < 1e-6][0][1]
        expected = START[3] + 0.4 * min(0.5 * speed, 2.0) / 2.0
        assert at.commands['right'][3] == pytest.approx(expected, abs=1e-6)
        finished_t = next(t for t, s in steps if s.phase == replay.FINISHED)
        assert finished_t - play_t == pytest.approx(2.0 / speed, abs=2 * PERIOD_S)
        assert core.progress() == pytest.approx((2.0, 2.0))


def test_a_speed_out_of_range_is_refused():
    for speed in (0.0, -1.0, replay.MAX_SPEED + 0.1):
        with pytest.raises(replay.ReplayError):
            replay.Replay(ramp_path(), {}, LIMITS, speed)


def test_the_approach_to_the_start_pose_is_slow_and_bounded():
    far = list(START)
    far[0] += 1.0
    core, first = started(ramp_path(), robot=far)
    assert first.phase == replay.APPROACH
    steps = [(0.0, first)] + run(core, 0.0, 6.0)
    approach = [s.commands['right'] for _, s in steps if s.phase == replay.APPROACH]
    previous = far
    for command in approach:
        step = max(abs(a - b) for a, b in zip(command, previous))
        assert step <= replay.APPROACH_SPEED_RAD_S * PERIOD_S * 1.01  # no jump
        previous = command
    assert approach[-1] == pytest.approx(START)
    assert len(approach) * PERIOD_S >= 1.0 / replay.APPROACH_SPEED_RAD_S - 0.05


def test_the_episode_plays_only_once_baxter_measures_the_start_pose():
    far = list(START)
    far[1] += 0.2
    core, _ = started(ramp_path(), robot=far)
    steps = run(core, 0.0, 2.0, follow=False)  # Baxter does not move: it never gets there
    assert all(s.phase == replay.APPROACH for t, s in steps)
    core.on_robot_pose(2.0, {'right': START})
    assert core.step(2.01).phase == replay.PLAY or core.step(2.02).phase == replay.PLAY


def test_a_jump_in_the_recording_is_played_within_the_velocity_limits():
    path = ramp_path()
    path['right'].values[100:, 0] += 1.0  # a 1 rad step halfway
    core, _ = started(path, speed=2.0)
    steps = run(core, 0.0, 3.0)
    commands = [s.commands['right'] for _, s in steps if s.phase == replay.PLAY]
    for a, b in zip(commands, commands[1:]):
        for j, lim in enumerate(LIMITS['right']):
            assert abs(b[j] - a[j]) <= lim.velocity * PERIOD_S * 1.0001
    assert steps[-1][1].phase == replay.FINISHED
    assert commands[-1][0] == pytest.approx(START[0] + 1.0)


def test_recorded_commands_outside_the_limits_are_clamped():
    path = ramp_path()
    upper = LIMITS['right'][3].upper
    path['right'].values[:, 3] = upper + 0.5
    core, _ = started(path, robot=[*START[:3], upper, *START[4:]])
    steps = run(core, 0.0, 3.0)
    assert all(s.commands['right'][3] <= upper for _, s in steps if s.commands)
    assert steps[-1][1].phase == replay.FINISHED


def test_gripper_goes_keep_in_step_with_the_arm():
    grips = {'right': [(4.0, 100.0), (5.5, 0.0), (6.5, 100.0), (9.0, 0.0)]}
    core, first = started(ramp_path(), grips, speed=2.0)
    assert first.grips == [replay.Grip('right', 100.0)]  # the gripper as at the start
    steps = run(core, 0.0, 2.0)
    play_t = next(t for t, s in steps if s.phase == replay.PLAY)
    sent = [(t - play_t, g.position) for t, s in steps for g in s.grips]
    # episode time 0.5 s and 1.5 s after the first command, at speed 2: 0.25 s and 0.75 s
    assert [p for _, p in sent] == [0.0, 100.0]
    assert [t for t, _ in sent] == pytest.approx([0.25, 0.75], abs=PERIOD_S + 1e-9)


@pytest.mark.parametrize('stop_rule, why', [
    (lambda core, t: core.on_button(t, BUTTON_OPMODE), 'button 1'),
    (lambda core, t: core.stop(t, 'stop requested'), 'stop requested'),
    (lambda core, t: core.on_puppet(t, 'R', [0.0, 0.0, 0.0, 0.15, 0.0, 0.0, 0.0]), 'moved'),
    (lambda core, t: core.on_robot_enabled(t, False), 'disabled'),
    (lambda core, t: core.on_following(t, True), 'following'),
])
def test_a_stop_rule_keeps_baxter_where_it_is_measured_at_once(stop_rule, why):
    core, _ = started(ramp_path())
    core.on_puppet(0.0, 'R', [0.0] * 7)
    run(core, 0.0, 1.0)
    measured = list(START)
    measured[3] += 0.123
    core.on_robot_pose(1.0, {'right': measured})
    stop_rule(core, 1.0)
    assert core.phase == replay.STOPPED and why in core.why
    for t in (1.01, 1.5):
        step = core.step(t)
        assert step.phase == replay.STOPPED
        assert step.commands['right'] == pytest.approx(measured)
        assert step.grips == []


def test_harmless_readings_do_not_stop():
    core, _ = started(ramp_path())
    core.on_puppet(0.0, 'R', [0.0] * 7)
    run(core, 0.0, 0.5)
    for t, feed in enumerate((lambda t: core.on_button(t, 0),
                              lambda t: core.on_button(t, BUTTON_RIGHT),
                              lambda t: core.on_puppet(t, 'R', [0.05] * 7),
                              lambda t: core.on_puppet(t, 'R', [math.nan] * 7),
                              lambda t: core.on_robot_enabled(t, True),
                              lambda t: core.on_following(t, False))):
        feed(0.5)
    assert core.phase != replay.STOPPED
    run(core, 0.5, 3.0)
    assert core.phase == replay.FINISHED
    core.on_button(3.0, BUTTON_OPMODE)  # after the end a stop changes nothing
    assert core.phase == replay.FINISHED and core.step(3.1).commands == {}


def test_start_needs_baxters_pose():
    core = replay.Replay(ramp_path(), {}, LIMITS)
    with pytest.raises(replay.ReplayError, match='unknown'):
        core.start(0.0)


def recording(command, go=None):
    return types.SimpleNamespace(command=command, gripper_go=go or {})


def test_the_script_holds_joints_a_command_did_not_name():
    values = np.array([[0.1] * 7, [np.nan, 0.2, np.nan, np.nan, np.nan, np.nan, np.nan]])
    rec = recording({'right': Samples(np.array([1.0, 2.0]), values),
                     'left': Samples(np.zeros(0), np.zeros((0, 7)))},
                    {'right': Samples(np.array([1.5]), np.array([[0.0]]))})
    paths, grips = replay.episode_script(rec)
    assert list(paths) == ['right']
    assert paths['right'].values[1].tolist() == [0.1, 0.2, 0.1, 0.1, 0.1, 0.1, 0.1]
    assert grips == {'right': [(1.5, 0.0)]}
    with pytest.raises(replay.ReplayError, match='left'):
        replay.episode_script(rec, ['left'])
    with pytest.raises(replay.ReplayError, match='no position commands'):
        replay.episode_script(recording({'right': Samples(np.zeros(0), np.zeros((0, 7)))}))


# ---- keep-out zones ------------------------------------------------------------------------

def capsules(side):
    with open(baxter_description.URDF_PATH) as urdf:
        return arm_capsules.ArmCapsules(baxter_description.load(), urdf.read(), side)


def zone_on_the_ramp():
    """A 3 cm sphere around the right gripper's finger halfway up ramp_path()'s joint 3 (the
    finger passes it 8 cm from the ramp's ends)."""
    arm = capsules('right')
    mid = list(START)
    mid[3] += 0.2
    finger = arm.segments([mid])[0, arm.links.index('r_gripper_r_finger')].mean(axis=1)
    return shapes.parse_shape({'name': 'test zone', 'type': 'sphere', 'radius': 0.03,
                               'xyz': finger.tolist()})


def guarded_run(path, robot, guards, t1=4.0):
    """Start and play with the robot following exactly; return (core, [Step], [commands sent to
    the right arm from Baxter's pose before the first to the last])."""
    core, first = started(path, robot=robot, guards=guards)
    steps = [first] + [s for _, s in run(core, 0.0, t1)]
    return core, steps, [list(robot)] + [s.commands['right'] for s in steps if s.commands]


def assert_never_into(guard, sent):
    """Check each motion from one command sent to the next at 40 points along it (steps of at
    most 0.6 mrad here) with the guard's own clearance: no capsule inside any zone."""
    for a, b in zip(sent, sent[1:]):
        for s in np.linspace(0.0, 1.0, 40):
            q = np.add(a, s * np.subtract(b, a))
            assert guard.clearance(q).min() > 0.0, 'a sent motion enters a zone at %s' % q


def test_an_episode_into_a_zone_waits_at_it_then_stops_naming_zone_link_and_arm():
    guard = zones.ZoneGuard(capsules('right'), [zone_on_the_ramp()])
    assert guard.clearance(START).min() > 0.05
    unguarded = guarded_run(ramp_path(), START, None)[2]   # without the guard: into the zone
    assert min(guard.clearance(q).min() for q in unguarded) < -0.02
    core, steps, sent = guarded_run(ramp_path(), START, {'right': guard})
    assert core.phase == replay.STOPPED
    assert re.fullmatch(r"keep-out zone 'test zone': (\w+) of the right arm would enter it",
                        core.why), core.why
    assert core.why.split(': ')[1].split()[0] in guard.capsules.links
    assert replay.PLAY in [s.phase for s in steps]          # it stopped in play ...
    assert guard.clearance(sent[-1]).min() < 0.01           # ... at the zone, not before
    assert_never_into(guard, sent)
    assert steps[-1].commands['right'] == sent[-1] and steps[-1].grips == []
    first_held = next(i for i, (a, b) in enumerate(zip(sent, unguarded)) if a != b)
    assert replay.PLAY in [s.phase for s in steps[:first_held]]   # unchanged up to the zone
    waited = sent[-int(replay.ZONE_WAIT_S / PERIOD_S):]   # then it waited at the zone, and
    assert len(sent) - 1 - first_held >= len(waited)      # stopped after ZONE_WAIT_S there
    assert max(guard.clearance(q).min() for q in waited) < 0.01


def test_a_stay_command_does_not_lead_into_a_zone_either():
    guard = zones.ZoneGuard(capsules('right'), [zone_on_the_ramp()])
    core, _ = started(ramp_path(), guards={'right': guard})
    run(core, 0.0, 0.5)
    last = core.step(0.5).commands['right']
    beyond = list(START)
    beyond[3] += 0.4   # Baxter measured past the zone (say a zone file changed): not there
    core.on_robot_pose(0.5, {'right': beyond})
    core.on_button(0.5, BUTTON_OPMODE)
    stay = core.step(0.51).commands['right']
    assert 'button 1' in core.why and stay != pytest.approx(beyond, abs=0.01)
    assert_never_into(guard, [last, stay])


def test_an_approach_across_a_zone_stops_before_it():
    guard = zones.ZoneGuard(capsules('right'), [zone_on_the_ramp()])
    far = list(START)
    far[3] += 0.4   # the approach back to START passes the zone; the episode leads away
    assert guard.clearance(far).min() > 0.05
    core, steps, sent = guarded_run(ramp_path(rise_rad=-0.3), far, {'right': guard})
    assert core.phase == replay.STOPPED and replay.PLAY not in [s.phase for s in steps]
    assert core.why.startswith("keep-out zone 'test zone': ")
    assert core.why.endswith('of the right arm would enter it on the way to the start pose')
    assert guard.clearance(sent[-1]).min() < 0.01
    assert_never_into(guard, sent)


def test_an_episode_clear_of_the_zones_plays_as_without_them():
    raised = [-0.2, -1.0, -0.3, 1.0, -0.3, 0.9, 0.25]   # tests/integration/hand_pose.py's
    path = ramp_path(rise_rad=0.4)
    path['right'].values[:] += np.subtract(raised, START)
    shipped = zones.load_zones(baxter_description.URDF_PATH.replace(
        'urdf/baxter.urdf', 'config/zones.yaml'))
    guard = zones.ZoneGuard(capsules('right'), shipped)
    far = list(raised)
    far[0] += 0.3
    plain, guarded = (guarded_run(path, far, guards)[1:] for guards in (None, {'right': guard}))
    assert guarded == plain and plain[0][-1].phase == replay.FINISHED


def test_an_arm_without_a_guard_is_not_checked():
    guard = zones.ZoneGuard(capsules('left'), [zone_on_the_ramp()])
    core, steps, sent = guarded_run(ramp_path(), START, {'left': guard})
    assert core.phase == replay.FINISHED and core.guards == {}
    assert sent == guarded_run(ramp_path(), START, None)[2]


def test_baxter_s_pose_counts_from_when_it_was_measured():
    core, _ = started(ramp_path())
    core.on_robot_pose(1.0, {'right': START}, age_s=0.05)
    assert core.robot.measured('right')[0] == pytest.approx(0.95)
    core.on_robot_pose(2.0, {'right': START}, age_s=-0.3)   # a stamp ahead: a clock apart
    assert core.robot.measured('right')[0] == 2.0
    core.on_robot_pose(3.0, {'right': START}, age_s=5.0)    # ... or behind: counted at most
    assert core.robot.measured('right')[0] == pytest.approx(3.0 - replay.MAX_POSE_AGE_S)
