"""The study runner's sequence: idle -> device -> trial ... -> questionnaire -> ... -> done.

Before every trial (the device phase): the trial's inputs ready, then no Baxter arm following
(the participant lets go: a press of the follow button), then both arms brought to their start,
Baxter's neutral pose (MoveArms: the adapter runs move_arms), so that every trial starts from the
same pose whatever the trials before it did.

Pure: time comes in as an argument (s, one clock: the adapter's ROS time), and what to do
goes out as actions (start or stop the inputs, start or stop an episode, write a CSV row,
summarise) for the node adapter (study_node) to carry out. The trial's judge and metrics are
the tasks' (TaskApi: study.tasks, task_judge and metrics), injectable for tests.
"""
import collections
import datetime

from robopuppet import interface
from robopuppet.study import plan as study_plan
from robopuppet.study import questionnaire, results

IDLE, DEVICE, TRIAL, QUESTIONNAIRE, DONE, STOPPED = (
    'idle', 'device', 'trial', 'questionnaire', 'done', 'stopped')  # StudyState's phases
RUNNING = (DEVICE, TRIAL, QUESTIONNAIRE)
EVENT_DEVICES = ('keyboard', 'gamepad', 'spacemouse')  # the devices read from an event source
READY_TIMEOUT_S = 60.0   # a device's inputs not ready (or the arms not let go) by then stop
MOVE_TRIES = 3           # the arms not brought to their start in this many tries stop the study
ARM_OF = interface.BAXTER_SIDE  # puppet side -> the Baxter arm its input drives

# Actions. StartInputs: stop what runs and start `device` on each of `sides` ({side: events
# path, '' for none}); StopInputs: stop them; Record: start (task text) or stop an episode;
# WriteRow: append `row` to the results file `name`; Summarize: write the study's summary;
# MoveArms: bring both arms to their start (move_arms), then call on_moved with its outcome.
StartInputs = collections.namedtuple('StartInputs', 'device events')
StopInputs = collections.namedtuple('StopInputs', '')
Record = collections.namedtuple('Record', 'start task')
WriteRow = collections.namedtuple('WriteRow', 'name row')
Summarize = collections.namedtuple('Summarize', '')
MoveArms = collections.namedtuple('MoveArms', '')

# What the adapter saw: ready {side: teleop_state ready or following}; tips {arm: (xyz, R)} or
# None before Baxter's first joint_states; closed, following, zone_held {arm: bool}.
Seen = collections.namedtuple('Seen', 'ready tips closed following zone_held')
# StudyState's content (goals: the judge's [Goal]).
State = collections.namedtuple('State', 'phase participant device task practice trial trials '
                                        'seed goals elapsed detail')
TaskApi = collections.namedtuple('TaskApi', 'make_trial judge metrics timeout_s')


def sides_of(task):
    """Return the puppet sides a task's inputs run on: L and R for bimanual, else R."""
    return ('L', 'R') if task == 'bimanual' else ('R',)


def iso_time(now):
    """Return a time (s since the epoch) as ISO 8601 in UTC, to the millisecond."""
    return datetime.datetime.fromtimestamp(now, datetime.timezone.utc).isoformat(
        timespec='milliseconds')


class StudyRun:
    """One participant's study at a time. Args: api (TaskApi), events {device: path}, study
    (its name, the rows' first column), defaults {devices, tasks, practice, trials, seed},
    trial_timeout_s (None: the task's own), ready_timeout_s."""

    def __init__(self, api, events, study, defaults, trial_timeout_s=None,
                 ready_timeout_s=READY_TIMEOUT_S):
        self._api, self._events, self._study = api, dict(events), study
        self._defaults, self._ready_timeout_s = dict(defaults), ready_timeout_s
        self._trial_timeout_s = trial_timeout_s
        self._phase, self._participant, self._detail = IDLE, '', 'no study runs'
        self._plan, self._k, self._inputs = [], 0, None  # the trial list, its current one, inputs
        self._since = self._t0 = 0.0   # when the DEVICE wait began; when the trial began
        self._moving, self._move_tries = False, 0   # the arms on their way to the start
        self._judge = self._metrics = self._made = None
        self._episode = ''

    @property
    def phase(self):
        """One of IDLE, DEVICE, TRIAL, QUESTIONNAIRE, DONE, STOPPED."""
        return self._phase

    @property
    def trial_judge(self):
        """The running trial's judge (None outside a trial), for its RViz markers."""
        return self._judge if self._phase == TRIAL else None

    def _current(self):
        """Return the trial running or next; in QUESTIONNAIRE the block's last one."""
        if not self._plan:
            return None
        k = self._k - 1 if self._phase == QUESTIONNAIRE else self._k
        return self._plan[min(k, len(self._plan) - 1)]

    def start(self, now, participant, index, devices=None, tasks=None):
        """Start a study for `participant` (index: 0-based among the study's participants).
        Returns (error, actions): error '' when started, else why nothing changed."""
        if self._phase in RUNNING:
            return 'a study runs (participant %s): stop it first' % self._participant, []
        devices = list(devices or self._defaults['devices'])
        tasks = list(tasks or self._defaults['tasks'])
        try:
            results.check_participant(participant)
            self._check(devices, tasks)
            plan = study_plan.make_plan(participant, index, devices, tasks,
                                        self._defaults['practice'], self._defaults['trials'],
                                        self._defaults['seed'])
        except (results.ResultsError, study_plan.PlanError, ValueError) as error:
            return str(error), []
        self._plan, self._k, self._participant = plan, 0, participant
        return '', self._next_trial(now)

    def _check(self, devices, tasks):
        """Raise ValueError for an unknown device or task, or a device with no event source."""
        for kind, names, known in (('device', devices, interface.STUDY_DEVICES),
                                   ('task', tasks, interface.STUDY_TASKS)):
            unknown = [n for n in names if n not in known]
            if unknown:
                raise ValueError('unknown %s %s (known: %s)' % (
                    kind, ', '.join(unknown), ', '.join(known)))
        missing = [d for d in devices if d in EVENT_DEVICES and not self._events.get(d)]
        if missing:
            raise ValueError('no event path for %s: set ~events (config/study.yaml) to the '
                             'device, e.g. /dev/input/by-id/...' % ', '.join(missing))

    def _next_trial(self, now):
        """Go to the current trial: start its inputs when they differ (DEVICE phase)."""
        trial = self._current()
        wanted = (trial.device, sides_of(trial.task))
        self._phase, self._since = DEVICE, now
        self._moving, self._move_tries = False, 0
        self._detail = 'starting %s for trial %d of %d' % (trial.device, trial.number,
                                                           len(self._plan))
        if wanted == self._inputs:
            return []
        self._inputs = wanted
        return [StartInputs(trial.device, {s: self._events.get(trial.device, '')
                                           for s in wanted[1]})]

    def stop(self, now, why='stopped by the operator'):
        """Stop the running study (inputs, episode); STOPPED with `why`. Returns actions."""
        del now
        if self._phase not in RUNNING:
            return []
        actions = [Record(False, '')] if self._phase == TRIAL else []
        self._phase, self._detail, self._inputs, self._moving = STOPPED, why, None, False
        return actions + [StopInputs()]

    def on_episode(self, now, episode):
        """Take the episode file the recorder started for the trial ('' none); the trial's
        time starts now, so that the recorder's start does not eat into it."""
        self._episode = episode
        if self._phase == TRIAL:
            self._start_clock(now)

    def step(self, now, seen):
        """Advance with what was seen (Seen). Returns actions."""
        if self._phase == DEVICE:
            return self._wait_ready(now, seen)
        if self._phase == TRIAL:
            return self._run_trial(now, seen)
        return []

    def on_moved(self, now, code, why):
        """Take move_arms' outcome: exit code 0 (the arms are at their start), else why not.
        Returns actions."""
        if self._phase != DEVICE or not self._moving:
            return []
        self._moving = False
        if code == 0:
            return self._begin(now, self._current())
        self._move_tries += 1
        if self._move_tries >= MOVE_TRIES:
            return self.stop(now, 'the arms were not brought to their start (%d tries): %s'
                             % (self._move_tries, why))
        self._detail = 'bringing the arms to their start again: %s' % why
        return []

    def _wait_ready(self, now, seen):
        if self._moving:
            return []
        trial = self._current()
        sides = sides_of(trial.task)
        late = [s for s in sides if not seen.ready.get(s)]
        held = [arm for arm, following in sorted(seen.following.items()) if following]
        if not (late or held):
            self._moving = True
            self._detail = ('bringing the arms to their start (Baxter\'s neutral pose) for '
                            'trial %d of %d' % (trial.number, len(self._plan)))
            return [MoveArms()]
        if held:
            self._detail = ('let go: press the follow button, so that the arms can be brought '
                            'to their start (the %s arm follows)' % ' and '.join(held))
        if now - self._since > self._ready_timeout_s:
            why = ('arm_%s not ready' % ' and arm_'.join(late) if late else
                   'the %s arm still following' % ' and '.join(held))
            return self.stop(now, '%s: %s %.0f s after the trial was due' % (
                trial.device, why, self._ready_timeout_s))
        return []

    def _begin(self, now, trial):
        self._made = self._api.make_trial(trial.task, trial.seed, practice=trial.practice)
        self._phase, self._episode = TRIAL, ''
        self._start_clock(now)
        return [Record(True, 'study: %s with %s, participant %s, trial %d' % (
            trial.task, trial.device, self._participant, trial.number))]

    def _start_clock(self, now):
        """Start the trial's judge and metrics (and its time) at `now`."""
        trial = self._current()
        self._t0 = now
        self._judge = self._api.judge(self._made, now, self.timeout_s(trial.task))
        self._metrics = self._api.metrics(self._made, now, self._judge)
        self._detail = 'trial %d of %d: %s' % (trial.number, len(self._plan), self._judge.detail)

    def timeout_s(self, task):
        """Return a task's trial timeout (s): ~trial_timeout when set, else the task's own."""
        return self._trial_timeout_s or self._api.timeout_s[task]

    def _run_trial(self, now, seen):
        trial = self._current()
        if seen.tips is not None:
            self._judge.update(now, seen.tips, seen.closed)
            self._metrics.update(now, seen.tips, seen.following, seen.zone_held, seen.closed)
        timed_out = now - self._t0 >= self.timeout_s(trial.task)
        self._detail = 'trial %d of %d: %s' % (trial.number, len(self._plan), self._judge.detail)
        if not (self._judge.done or timed_out):
            return []
        row = dict.fromkeys(results.TRIAL_COLUMNS, '')
        row.update(self._metrics.row())
        success = bool(self._judge.done and self._judge.success)
        row.update(study=self._study, participant=self._participant, device=trial.device,
                   task=trial.task, trial=trial.number, practice=trial.practice,
                   seed=trial.seed, started=iso_time(self._t0), success=success,
                   episode=self._episode)
        actions = [Record(False, ''), WriteRow(results.TRIALS_CSV, row)]
        self._k += 1
        if self._k < len(self._plan) and self._plan[self._k].device == trial.device:
            return actions + self._next_trial(now)
        self._phase = QUESTIONNAIRE
        self._detail = 'answer the questionnaire about %s' % trial.device
        return actions

    def questionnaire(self, now, participant, device, tlx, sus):
        """Take a participant's answers about a device. Returns (error, actions): error ''
        when they were taken (and the study moved on), else why they were ignored."""
        trial = self._current()
        if self._phase != QUESTIONNAIRE:
            return 'no questionnaire is awaited (phase %s)' % self._phase, []
        if (participant, device) != (self._participant, trial.device):
            return 'answers about %s by %s, but %s about %s awaited' % (
                device, participant, self._participant, trial.device), []
        tlx, sus = [float(r) for r in tlx], [int(a) for a in sus]
        why = questionnaire.check_answers(tlx, sus)
        if why:
            return why, []
        row = dict(zip(results.TLX_COLUMNS, tlx), **dict(zip(results.SUS_COLUMNS, sus)))
        row.update(participant=participant, device=device, tlx=questionnaire.tlx_raw(tlx),
                   sus=questionnaire.sus_score(sus))
        actions = [WriteRow(results.QUESTIONNAIRE_CSV, row)]
        if self._k < len(self._plan):
            self._phase = DEVICE
            return '', actions + self._next_trial(now)
        self._phase, self._inputs = DONE, None
        self._detail = 'study complete: %d trials' % len(self._plan)
        return '', actions + [StopInputs(), Summarize()]

    def state(self, now):
        """Return the State to publish now."""
        trial = self._current() if self._phase in RUNNING else None
        goals = self._judge.goals(now) if self._phase == TRIAL else []
        elapsed = now - self._t0 if self._phase == TRIAL else 0.0
        if trial is None:
            return State(self._phase, self._participant, '', '', False, 0, len(self._plan), 0,
                         [], 0.0, self._detail)
        return State(self._phase, self._participant, trial.device, trial.task, trial.practice,
                     trial.number, len(self._plan), trial.seed, goals, elapsed, self._detail)
