"""Unit tests of playback into the puppet: hold first, a slow approach, the recorded timing at a
speed factor, bounded setpoint speed, angle limits, refusals, every stop, and the tracking
watch's stops (limp, and why)."""
import math

import numpy as np
import pytest

from robopuppet import settings
from robopuppet.episodes import puppet_playback as pp
from robopuppet.episodes import replay_control
from robopuppet.episodes import tracking_watch as tw
from robopuppet.episodes.export import Recording, Samples
from robopuppet.episodes.replay import APPROACH, FINISHED, PLAY, STOPPED, ReplayError
from robopuppet.interface import BUTTON_OPMODE, BUTTON_RIGHT, HOLD, LIMP, UNCALIBRATED, WORKING

PERIOD_S = 0.02
START = [0.1, -0.3, 0.2, 1.0, -0.1, 0.5, 0.0]


def ramp(duration_s=2.0, joint=3, rise_rad=0.4, t0=5.0, rate_hz=10.0):
    """Puppet R recorded at 10 Hz from START, `joint` rising linearly by rise_rad."""
    times = t0 + np.arange(0.0, duration_s + 1e-9, 1.0 / rate_hz)
    values = np.tile(START, (len(times), 1))
    values[:, joint] += rise_rad * (times - t0) / duration_s
    return {'R': Samples(times, values)}


def stored(changes):
    """Stored settings of the 7 joints: the defaults, with {(joint, name): value} changes."""
    table = {j: dict(settings.DEFAULTS) for j in settings.JOINTS}
    for (joint, name), value in changes.items():
        table[joint][name] = value
    return table


def ready(paths, here=START, t=0.0, stored_settings=None, **kwargs):
    """A playback whose puppet R reports `here`, every joint Working."""
    core = pp.PuppetPlayback(paths, period_s=PERIOD_S, **kwargs)
    core.on_puppet(t, 'R', list(here))
    for joint in settings.JOINTS:
        core.on_status(t, 'R', joint, WORKING)
    if stored_settings is not None:
        core.on_settings(t, 'R', stored_settings)
    return core


def started(paths, *args, **kwargs):
    """A playback as ready() makes it, started at time 0."""
    core = ready(paths, *args, **kwargs)
    core.start(0.0)
    return core


def run(core, t0, t1, follow=True):
    """Step from t0 to t1; the puppet measures its setpoints when follow (a stiff PID)."""
    steps, t = [], t0
    while t < t1 - 1e-9:
        t += PERIOD_S
        step = core.step(t)
        steps.append((t, step))
        if follow and 'R' in step.setpoints:
            core.on_puppet(t, 'R', step.setpoints['R'])
        elif not follow:
            core.on_puppet(t, 'R', core._angles['R'])  # fresh joint states, not moving
    return steps


def test_start_holds_the_puppet_where_it_is_setpoints_first():
    here = [0.3, 0.2, -0.1, 0.9, 0.0, 0.4, 0.1]
    core = ready(ramp(), here)
    first = core.start(0.0)
    assert first == pp.Step(APPROACH, {'R': here}, {'R': HOLD})


def test_the_approach_moves_at_the_approach_speed_and_never_steps():
    far = list(START)
    far[0] += 0.3   # 0.3 rad away at 0.3 rad/s: 1 s of approach
    far[5] -= 0.15
    core = started(ramp(), far)
    steps = run(core, 0.0, 3.0)
    approach = [(t, s.setpoints['R']) for t, s in steps if s.phase == APPROACH]
    previous = far
    for _, setpoints in approach:
        assert max(abs(a - b) for a, b in zip(setpoints, previous)) <= 0.3 * PERIOD_S + 1e-12
        previous = setpoints
    half = [q for t, q in approach if abs(t - 0.5) < 1e-9][0]
    assert half[0] == pytest.approx(START[0] + 0.15) and half[5] == pytest.approx(START[5])
    assert approach[-1][1] == pytest.approx(START)
    assert approach[-1][0] == pytest.approx(1.0, abs=1.5 * PERIOD_S)


def test_the_episode_plays_once_the_puppet_measures_the_start_pose_or_after_a_while():
    far = list(START)
    far[1] += 0.2
    core = started(ramp(), far)
    steps = run(core, 0.0, 3.0, follow=False)  # held back: it never gets there
    assert all(s.phase == APPROACH for _, s in steps)
    core.on_puppet(3.0, 'R', [a + 0.015 for a in START])  # within 0.02 rad
    core.step(3.02)
    assert core.phase == PLAY
    stuck = ready(ramp(), far)
    stuck.start(0.0)
    steps = run(stuck, 0.0, 0.67 + pp.SETTLE_TIMEOUT_S + 0.1, follow=False)
    played = next(t for t, s in steps if s.phase == PLAY)
    assert played == pytest.approx(0.2 / 0.3 + pp.SETTLE_TIMEOUT_S, abs=2 * PERIOD_S)


@pytest.mark.parametrize('speed', [0.5, 1.0, 2.0])
def test_the_recorded_timing_times_the_speed_factor(speed):
    core = started(ramp(), speed=speed)
    steps = run(core, 0.0, 2.0 / speed + 0.5)
    play_t = [t for t, s in steps if s.phase == APPROACH][-1]  # episode time 0 (5.0 s recorded)
    at = [s for t, s in steps if abs(t - play_t - 0.4) < 1e-9][0]
    # 0.4 s after the start the episode is at 0.4 x speed s of 2 s: the ramp at 0.2 x speed
    assert at.setpoints['R'][3] == pytest.approx(START[3] + 0.4 * 0.4 * speed / 2.0)
    finished_t = next(t for t, s in steps if s.phase == FINISHED)
    # finished once the puppet measures the last setpoints: here one period after them
    assert finished_t - play_t == pytest.approx(2.0 / speed + PERIOD_S, abs=2 * PERIOD_S)
    assert steps[-1][1] == pp.Step(FINISHED, {}, {})
    assert core.progress() == pytest.approx((2.0, 2.0))
    assert core.outcome('R') == ('puppet arm R holds the last recorded pose (measured within '
                                 '0.00 rad)')


def test_a_speed_out_of_range_is_refused():
    for speed in (0.0, -1.0, 2.5, math.nan):
        with pytest.raises(ReplayError, match='speed'):
            pp.PuppetPlayback(ramp(), speed)


def test_a_jump_in_the_recording_is_played_at_the_play_speed_or_the_stored_limit():
    path = ramp()
    path['R'].values[10:, 0] += 1.0   # a 1 rad step at 1 s
    for limits, speed in ((None, pp.PLAY_SPEED_RAD_S),
                          (stored({(0, 'velocity_max'): 0.5}), 0.5),
                          (stored({(0, 'velocity_min'): -0.8}), 0.8)):
        core = started(path, stored_settings=limits, speed=2.0)
        setpoints = [s.setpoints['R'] for _, s in run(core, 0.0, 4.0) if s.phase == PLAY]
        steps = [abs(b[0] - a[0]) for a, b in zip(setpoints, setpoints[1:])]
        assert max(steps) == pytest.approx(speed * PERIOD_S)  # the bound, and reached
        assert setpoints[-1][0] == pytest.approx(START[0] + 1.0)


def test_setpoints_stay_within_the_stored_angle_limits():
    path = ramp(joint=0, rise_rad=0.6)                 # recorded up to 0.7 rad
    core = started(path, stored_settings=stored({(0, 'angle_max'): 0.45}))
    steps = run(core, 0.0, 4.0)
    assert core.limit_source['R'] == 'the stored settings'
    assert max(s.setpoints['R'][0] for _, s in steps if s.setpoints) == pytest.approx(0.45)
    assert steps[-1][1].phase == FINISHED


def test_without_stored_settings_the_limits_are_the_recorded_range():
    path = ramp(joint=0, rise_rad=0.6)
    limits, source = pp.joint_limits(None, path['R'])
    assert source == 'the recorded range'
    assert (limits[0].lower, limits[0].upper) == pytest.approx((0.1, 0.7))
    assert (limits[3].lower, limits[3].upper) == pytest.approx((1.0, 1.0))
    far = list(START)
    far[3] = 1.4                      # joint 3 was never recorded away from 1.0
    core = ready(path, far)
    first = core.start(0.0)
    assert first.setpoints['R'][3] == 1.4  # the hold is where the puppet is: no step
    steps = run(core, 0.0, 4.0)
    assert steps[-1][1].phase == FINISHED
    assert all(s.setpoints['R'][3] >= 1.0 - 1e-12 for _, s in steps if s.setpoints)
    assert core.limit_source['R'] == 'the recorded range'


def test_stored_limits_that_are_no_range_are_refused():
    with pytest.raises(ReplayError, match='joint 2'):
        pp.joint_limits(stored({(2, 'angle_min'): 1.0, (2, 'angle_max'): 0.5}), None)


@pytest.mark.parametrize('stop, why', [
    (lambda core, t: core.on_button(t, 'R', BUTTON_OPMODE), 'button 1 pressed on puppet arm R'),
    (lambda core, t: core.stop(t, 'stop requested'), 'stop requested'),
    (lambda core, t: core.on_status(t, 'R', 2, UNCALIBRATED), 'joint 2 is Uncalibrated'),
])
def test_a_stop_holds_the_last_setpoints_at_once(stop, why):
    core = started(ramp())
    steps = run(core, 0.0, 1.0)
    assert steps[-1][1].phase == PLAY
    last = steps[-1][1].setpoints['R']
    stop(core, 1.0)
    after = run(core, 1.0, 1.5)
    assert core.phase == STOPPED and why in core.why
    assert all(s == pp.Step(STOPPED, {'R': last}, {}) for _, s in after)
    assert core.outcome('R') == 'puppet arm R holds where it is'


def test_other_buttons_do_not_stop():
    core = started(ramp())
    run(core, 0.0, 0.5)
    core.on_button(0.5, 'R', BUTTON_RIGHT)   # Baxter follows, as she chooses
    core.on_button(0.5, 'R', 0)
    assert core.phase == PLAY


def test_a_limp_from_another_node_stops_and_that_side_stays_limp():
    core = started(ramp())
    run(core, 0.0, 1.0)
    core.on_opmode(1.0, 'R', HOLD, '/gui_R')   # a hold changes nothing
    assert core.phase == PLAY
    core.on_opmode(1.0, 'R', LIMP, '/gui_R')
    assert core.phase == STOPPED and core.why == 'puppet arm R was put limp by /gui_R'
    assert core.step(1.02) == pp.Step(STOPPED, {}, {})  # no setpoints into a limp puppet
    assert core.outcome('R') == 'puppet arm R is limp (put limp by /gui_R)'


def test_button_1_then_arm_x_releasing_the_puppet_it_held_leaves_it_limp():
    core = started(ramp())
    run(core, 0.0, 1.0)
    core.on_button(1.0, 'R', BUTTON_OPMODE)
    assert core.step(1.02).setpoints                     # the stay goes out at once
    core.on_opmode(1.03, 'R', LIMP, '/arm_R')            # arm_X's toggle of a held puppet
    assert core.step(1.04) == pp.Step(STOPPED, {}, {})
    assert core.why == 'button 1 pressed on puppet arm R'


def test_a_puppet_going_silent_stops_the_playback():
    core = started(ramp())
    run(core, 0.0, 1.0)
    last = core.step(1.0).setpoints['R']
    step = core.step(1.0 + pp.SILENT_S + 0.01)   # no joint states since t = 1.0
    assert core.phase == STOPPED and 'went silent' in core.why
    assert step.setpoints == {'R': last}


@pytest.mark.parametrize('feed, why', [
    (lambda core: None, 'puppet arm R is silent: no joint states'),
    (lambda core: core.on_puppet(0.0, 'R', START), 'joints 0, 1, 2, 3, 4, 5, 6 with no encoder'),
    (lambda core: [core.on_puppet(0.0, 'R', START)] + [
        core.on_status(0.0, 'R', j, UNCALIBRATED if j in (0, 2) else WORKING)
        for j in settings.JOINTS], 'joints 0, 2 Uncalibrated (turn each through its index'),
])
def test_a_puppet_not_there_or_not_calibrated_is_refused(feed, why):
    core = pp.PuppetPlayback(ramp(), period_s=PERIOD_S)
    feed(core)
    assert why in core.refusal(0.5)
    with pytest.raises(ReplayError, match='puppet arm R'):
        core.start(0.5)
    assert core.phase is None


def test_a_puppet_silent_for_too_long_is_refused():
    core = ready(ramp())
    assert core.refusal(pp.SILENT_S - 0.01) == ''
    assert 'silent: no joint states for' in core.refusal(pp.SILENT_S + 0.01)


def test_puppet_paths_drop_incomplete_joint_states_and_need_some():
    values = np.array([START, [math.nan] + START[1:], START])
    puppet = {'R': Samples(np.array([0.0, 0.1, 0.2]), values),
              'L': Samples(np.zeros(0), np.zeros((0, 7)))}
    recording = Recording(*[None] * 4, gripper_state=None, gripper_force=None, gripper_go=None,
                          puppet=puppet, end_piece=None, follow=None)
    paths = pp.puppet_paths(recording, ['R'])
    assert list(paths['R'].times) == [0.0, 0.2]
    with pytest.raises(ReplayError, match='no joint states of puppet arm L'):
        pp.puppet_paths(recording, ['L'])


# ---- the tracking watch (robopuppet.episodes.tracking_watch) in the playback ----------------

def hold_back(core, t0, t1, angles, volts, side='R'):
    """Step from t0 to t1; the puppet reports angles (rad; a function of the setpoints sent,
    or fixed) and volts (V) after each step."""
    steps, t, sent = [], t0, None
    while t < t1 - 1e-9:
        t += PERIOD_S
        step = core.step(t)
        steps.append((t, step))
        sent = step.setpoints.get(side, sent)
        here = angles(sent) if callable(angles) else angles
        core.on_puppet(t, side, list(here), list(volts))
    return steps


def test_a_puppet_that_does_not_follow_goes_limp_and_says_why():
    # The new user's puppet: held where it is, every motor at its voltage limit.
    core = started(ramp(rise_rad=1.0))
    steps = hold_back(core, 0.0, 4.0, START, [7.2] * 7)
    play_t = next(t for t, s in steps if s.phase == PLAY)
    stop_t, stop = next((t, s) for t, s in steps if s.phase == STOPPED)
    # joint 3's setpoint rises 0.5 rad/s: beyond FOLLOW_ERROR_RAD after 0.6 s, then the time
    assert stop_t - play_t == pytest.approx(tw.FOLLOW_ERROR_RAD / 0.5 + tw.FOLLOW_TIME_S,
                                            abs=2 * PERIOD_S)
    assert stop == pp.Step(STOPPED, {}, {'R': LIMP})      # limp, once; no setpoints after
    assert all(s == pp.Step(STOPPED, {}, {}) for t, s in steps if t > stop_t)
    assert core.why == ('puppet arm R does not follow: joint 3 0.80 rad from its setpoint for '
                        '1.0 s at 7.20 V (saturated)')
    assert core.outcome('R') == 'puppet arm R went limp'


def test_a_motor_saturated_too_long_goes_limp_however_close():
    core = started(ramp(duration_s=3.0))
    volts = [0.0, 0.0, -7.2, 0.0, 0.0, 0.0, 0.0]
    steps = hold_back(core, 0.0, 4.0, lambda sent: sent, volts)   # on its setpoints
    stop_t, stop = next((t, s) for t, s in steps if s.phase == STOPPED)
    # saturated from the first sample (after the first step), stopped at the step after that
    assert stop_t == pytest.approx(2 * PERIOD_S + tw.SATURATION_MAX_S, abs=1e-9)
    assert stop.opmodes == {'R': LIMP}
    assert core.why == ('puppet arm R pushes at its voltage limit too long: joint 2 at -7.20 V '
                        'for 2.0 s, 0.00 rad from its setpoint (to protect the motors)')


@pytest.mark.parametrize('off_rad, finished', [(tw.FINAL_TOLERANCE_RAD - 0.01, True),
                                               (tw.FINAL_TOLERANCE_RAD + 0.01, False)])
def test_finished_only_when_the_puppet_measures_the_last_pose(off_rad, finished):
    core = started(ramp())
    steps = hold_back(core, 0.0, 8.0, lambda sent: [a + (off_rad if j == 5 else 0.0)
                                                     for j, a in enumerate(sent)], [1.0] * 7)
    play_t = next(t for t, s in steps if s.phase == PLAY)
    arrived_t = play_t + 2.0     # the 2 s episode
    if finished:
        assert core.phase == FINISHED
        assert core.outcome('R') == ('puppet arm R holds the last recorded pose (measured '
                                     'within 0.04 rad)')
        return
    stop_t, stop = next((t, s) for t, s in steps if s.phase == STOPPED)
    assert stop_t - arrived_t == pytest.approx(tw.FINAL_TIMEOUT_S, abs=2 * PERIOD_S)
    assert all(s.phase == PLAY for t, s in steps if play_t <= t < stop_t)  # the last pose
    assert stop.opmodes == {'R': LIMP}
    assert core.why == ('puppet arm R did not reach the last recorded pose within 0.05 rad '
                        '4.0 s after the last setpoints: joint 5 0.06 rad from it at 1.00 V')
    assert core.outcome('R') == 'puppet arm R went limp'


def test_a_puppet_that_never_moves_and_reports_no_voltages_is_not_finished():
    core = started(ramp(rise_rad=1.0))
    steps = run(core, 0.0, 10.0, follow=False)       # no voltages: only the end is watched
    assert not any(s.phase == FINISHED for _, s in steps)
    assert core.phase == STOPPED and 'joint 3 1.00 rad from it at an unknown voltage' in core.why


def test_only_the_side_that_does_not_follow_goes_limp_the_other_holds():
    paths = dict(ramp(rise_rad=1.0), L=ramp(rise_rad=1.0)['R'])
    core = pp.PuppetPlayback(paths, period_s=PERIOD_S)
    for side in 'LR':
        core.on_puppet(0.0, side, START)
        for joint in settings.JOINTS:
            core.on_status(0.0, side, joint, WORKING)
    core.start(0.0)
    t, sent = 0.0, {}
    while core.phase != STOPPED:
        t += PERIOD_S
        step = core.step(t)
        sent.update(step.setpoints)
        core.on_puppet(t, 'L', sent['L'], [0.5] * 7)           # L follows
        core.on_puppet(t, 'R', START, [7.2] * 7)               # R is held
    step = core.step(t + PERIOD_S)
    assert step == pp.Step(STOPPED, {'L': sent['L']}, {'R': LIMP})
    assert core.outcome('L') == 'puppet arm L holds where it is'
    assert core.outcome('R') == 'puppet arm R went limp'


def test_the_guis_replay_box_shows_the_tracking_stop_in_the_players_words():
    core = started(ramp(rise_rad=1.0))
    hold_back(core, 0.0, 4.0, START, [-7.2] * 7)
    line = 'replay: stopped: %s; %s\n' % (core.why, core.outcome('R'))  # as puppet_player says
    shown = replay_control.exit_text(1, replay_control.state_from_line(line))
    assert shown == ('stopped: puppet arm R does not follow: joint 3 0.80 rad from its setpoint '
                     'for 1.0 s at -7.20 V (saturated); puppet arm R went limp (exit 1: stopped '
                     'by a stop rule)')
