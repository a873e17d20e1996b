"""Unit tests of study.study_run: the runner's sequence with a stand-in judge and metrics."""
import pytest

from robopuppet.study import results, study_run as sr

EVENTS = {'keyboard': '/tmp/kb', 'gamepad': '/dev/input/by-id/pad'}
TIMEOUT_S = {'reach_hold': 30.0, 'trace': 60.0, 'pick_place': 60.0, 'bimanual': 60.0}
TLX, SUS = [50.0] * 6, [3] * 10


class Judge:
    """Stand-in for tasks' TrialJudge: done when the tip reaches x >= 1."""
    made = []

    def __init__(self, trial, t0, timeout_s):
        self.trial, self.t0, self.done, self.success, self.detail = trial, t0, False, False, 'go'
        Judge.made.append(self)

    def update(self, t, tips, closed):
        if tips['right'][0][0] >= 1.0:
            self.done = self.success = True

    def goals(self, t):
        return [] if self.done else ['goal']


class Metrics:
    def __init__(self, trial, t0, judge):
        self.seen = []

    def update(self, t, tips, following, zone_held, closed):
        self.seen.append(t)

    def row(self):
        return {'completion_s': 1.25, 'success': None, 'path_m': 0.5, 'jerk': 2.0,
                'zone_s': 0.0, 'clutches': 1, 'idle_s': 0.1}


def make_run(trial_timeout_s=None, **defaults):
    api = sr.TaskApi(lambda task, seed, practice: (task, seed, practice), Judge, Metrics,
                     TIMEOUT_S)
    settings = dict(devices=['keyboard'], tasks=['reach_hold'], practice=0, trials=1, seed=1)
    settings.update(defaults)
    return sr.StudyRun(api, EVENTS, 'pilot', settings, trial_timeout_s, ready_timeout_s=20.0)


def seen(ready=('R',), x=0.0):
    tips = {'right': ((x, 0.0, 0.0), None), 'left': ((0.0, 0.0, 0.0), None)}
    return sr.Seen({s: True for s in ready}, tips, {'right': False, 'left': False},
                   {'right': False, 'left': False}, {'right': False, 'left': False})


def begin(run, t, saw=None):
    """Step the DEVICE phase at t: the arms go to their start (MoveArms), move_arms ends well,
    the trial begins; return the actions of its beginning."""
    assert run.step(t, saw or seen()) == [sr.MoveArms()]
    assert run.phase == sr.DEVICE and 'start' in run.state(t).detail
    return run.on_moved(t, 0, '')


def rows(actions, name=results.TRIALS_CSV):
    return [a.row for a in actions if isinstance(a, sr.WriteRow) and a.name == name]


def test_a_study_runs_through_trials_and_questionnaires_to_done():
    run = make_run(devices=['keyboard', 'gamepad'], tasks=['reach_hold', 'bimanual'])
    error, actions = run.start(100.0, 'P01', 0)
    assert error == '' and run.phase == sr.DEVICE
    first = run.state(100.0).device
    assert actions == [sr.StartInputs(first, {'R': EVENTS[first]})]
    assert run.step(101.0, seen(ready=())) == [] and run.phase == sr.DEVICE
    written, starts = [], []
    for block in range(2):
        for _ in range(2):
            task = run.state(102.0).task
            actions = begin(run, 102.0, seen(ready=('L', 'R')))
            assert actions[0].start and 'study: %s with ' % task in actions[0].task
            assert run.phase == sr.TRIAL and run.state(103.0).elapsed == 1.0
            assert run.state(103.0).goals == ['goal']
            actions = run.step(103.0, seen(x=2.0))    # the judge says done
            written += rows(actions)
            starts += [a for a in actions if isinstance(a, sr.StartInputs)]
        assert run.phase == sr.QUESTIONNAIRE
        device = run.state(104.0).device
        error, actions = run.questionnaire(104.0, 'P01', device, TLX, SUS)
        assert error == ''
        answers = rows(actions, results.QUESTIONNAIRE_CSV)[0]
        assert answers['tlx'] == 50.0 and answers['sus'] == 50.0 and answers['device'] == device
        starts += [a for a in actions if isinstance(a, sr.StartInputs)]
    assert run.phase == sr.DONE
    assert actions[-2:] == [sr.StopInputs(), sr.Summarize()]
    assert [r['trial'] for r in written] == [1, 2, 3, 4]
    assert all(r['success'] is True and r['completion_s'] == 1.25 for r in written)
    assert set(written[0]) == set(results.TRIAL_COLUMNS)
    # inputs restart only when the device or the sides change: bimanual runs L and R
    assert [sorted(s.events) for s in starts] in (
        [['L', 'R'], ['R'], ['L', 'R']], [['R'], ['L', 'R'], ['R']])


def test_a_trial_not_done_by_its_timeout_fails():
    run = make_run(trial_timeout_s=5.0, trials=2)
    run.start(0.0, 'P01', 0)
    begin(run, 1.0)
    assert rows(run.step(5.9, seen())) == []
    actions = run.step(6.0, seen())
    assert actions[0] == sr.Record(False, '')
    row = rows(actions)[0]
    assert row['success'] is False and row['path_m'] == 0.5
    assert run.phase == sr.DEVICE     # the same input: the next trial starts when ready
    assert not [a for a in actions if isinstance(a, sr.StartInputs)]
    assert run.timeout_s('trace') == 5.0 and make_run().timeout_s('trace') == 60.0


def test_the_trial_time_starts_once_its_episode_started():
    run = make_run(trial_timeout_s=5.0)
    run.start(0.0, 'P01', 0)
    begin(run, 1.0)
    run.on_episode(3.0, '/episodes/e1.bag')    # the recorder took 2 s to start
    assert Judge.made[-1].t0 == 3.0 and run.state(4.0).elapsed == 1.0
    assert run.step(7.0, seen()) == []
    row = rows(run.step(8.0, seen()))[0]
    assert row['episode'] == '/episodes/e1.bag' and row['started'].endswith('00:00:03.000+00:00')


def test_stop_ends_the_episode_and_the_inputs():
    run = make_run()
    run.start(0.0, 'P01', 0)
    begin(run, 1.0)
    assert run.stop(2.0) == [sr.Record(False, ''), sr.StopInputs()]
    assert run.phase == sr.STOPPED and 'operator' in run.state(2.0).detail
    assert run.step(3.0, seen(x=2.0)) == [] and run.stop(3.0) == []
    assert run.start(4.0, 'P01', 0)[0] == ''   # a new study may start


def test_the_questionnaire_waits_for_its_participant_and_device_and_valid_answers():
    run = make_run()
    run.start(0.0, 'P01', 0)
    begin(run, 1.0)
    run.step(2.0, seen(x=2.0))
    assert run.phase == sr.QUESTIONNAIRE
    assert 'awaited' in run.questionnaire(3.0, 'P02', 'keyboard', TLX, SUS)[0]
    assert 'awaited' in run.questionnaire(3.0, 'P01', 'gamepad', TLX, SUS)[0]
    assert 'SUS' in run.questionnaire(3.0, 'P01', 'keyboard', TLX, [3] * 9)[0]
    assert run.phase == sr.QUESTIONNAIRE and run.step(4.0, seen()) == []
    assert run.questionnaire(5.0, 'P01', 'keyboard', TLX, bytes(SUS))[0] == ''
    assert run.phase == sr.DONE


@pytest.mark.parametrize('devices, expected', [
    (['spacemouse'], 'no event path for spacemouse'), (['joystick'], 'unknown device')])
def test_a_device_without_an_event_path_or_unknown_is_refused(devices, expected):
    run = make_run()
    error, actions = run.start(0.0, 'P01', 0, devices=devices)
    assert expected in error and actions == [] and run.phase == sr.IDLE


def test_puppet_and_marker_need_no_event_path_and_bad_ids_are_refused():
    assert make_run().start(0.0, 'P01', 0, devices=['puppet', 'marker'])[0] == ''
    assert 'participant' in make_run().start(0.0, 'P 1', 0)[0]
    run = make_run()
    run.start(0.0, 'P01', 0)
    assert 'stop it first' in run.start(1.0, 'P02', 1)[0]


def test_inputs_never_ready_stop_the_study():
    run = make_run()
    run.start(0.0, 'P01', 0)
    assert run.step(19.0, seen(ready=())) == []
    assert run.step(21.0, seen(ready=())) == [sr.StopInputs()]
    assert run.phase == sr.STOPPED and 'arm_R not ready' in run.state(21.0).detail


def test_the_arms_go_to_their_start_once_let_go_and_a_failed_move_is_tried_again():
    run = make_run(trials=2)
    run.start(0.0, 'P01', 0)
    following = seen()._replace(following={'right': True, 'left': False})
    assert run.step(1.0, following) == []          # the arm follows: nothing moves it
    assert 'let go' in run.state(1.0).detail and 'right arm' in run.state(1.0).detail
    assert run.step(2.0, seen()) == [sr.MoveArms()]
    assert run.step(2.5, seen()) == []             # one move at a time
    assert run.on_moved(3.0, 1, 'stopped: the puppet started following') == []
    assert 'again' in run.state(3.0).detail and run.phase == sr.DEVICE
    assert run.step(3.5, seen()) == [sr.MoveArms()]
    actions = run.on_moved(4.0, 0, '')
    assert actions[0].start and run.phase == sr.TRIAL
    assert run.on_moved(4.5, 0, '') == []          # late or repeated outcomes change nothing
    actions = run.step(5.0, seen(x=2.0))           # done; the next trial: let go, move again
    assert run.phase == sr.DEVICE and run.step(5.5, following) == []
    assert begin(run, 6.0)[0].start and run.phase == sr.TRIAL


def test_arms_never_brought_to_their_start_or_never_let_go_stop_the_study():
    run = make_run()
    run.start(0.0, 'P01', 0)
    for k in range(sr.MOVE_TRIES):
        assert run.step(1.0 + k, seen()) == [sr.MoveArms()]
        actions = run.on_moved(1.5 + k, 2, "refused: keep-out zone 'bed'")
    assert actions == [sr.StopInputs()] and run.phase == sr.STOPPED
    assert "3 tries): refused: keep-out zone 'bed'" in run.state(9.0).detail
    run = make_run()
    run.start(0.0, 'P01', 0)
    held = seen()._replace(following={'right': False, 'left': True})
    assert run.step(19.0, held) == []
    assert run.step(21.0, held) == [sr.StopInputs()]
    assert 'the left arm still following' in run.state(21.0).detail
