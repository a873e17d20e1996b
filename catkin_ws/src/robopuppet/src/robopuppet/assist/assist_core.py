"""What the assist does each step: the assisted arm's target, its ghost and the assist's state.

The assist node's only entry point (pure: no rospy, time passed in, seconds of one monotonic
clock). Inputs: the model (on_model), the leader arm's measured pose (on_leader_pose), the
GUI's stop and start (on_command), whether the leader's arm controller drives the assisted arm
from the assist (on_teleop_state). step(t) says what to publish.

Rules for the target's hold (the leader's arm_X then holds the assisted arm where it is):
  - stopped on request, until 'start';
  - the leader's pose is older than leader_timeout_s, or none came yet;
  - the motion is unfamiliar: at once when a prediction is not familiar; the assist resumes
    only after resume_after_s of familiar predictions (also at start and after a stale pose).
A hold target still carries the newest valid prediction's pose; none is sent before the first.
"""
import collections
import math

from robopuppet.baxter_description import arm_joint_names
from robopuppet.interface import ASSIST_COMMANDS, BAXTER_SIDE, BAXTER_SIDES, BUTTON_LEFT, \
    BUTTON_RIGHT

OFF, READY, ASSISTING, HOLDING, STOPPED = 'off', 'ready', 'assisting', 'holding', 'stopped'
STATE_PERIOD_S = 0.5     # the state goes out at least this often
# A leader pose older than this (s) holds the assisted arm: twenty periods of Baxter's 100 Hz
# joint states, so that a loaded host's short stalls do not; as arm_X's timeout on targets.
LEADER_TIMEOUT_S = 0.2
CONFIDENCE_STEP = 0.05   # a confidence change this large is news (at most every 0.1 s)
CONFIDENCE_PERIOD_S = 0.1
GHOST_RATE_HZ = 25.0     # the ghost node draws at 20 Hz: more would be wasted
PUPPET_OF = {arm: puppet for puppet, arm in BAXTER_SIDE.items()}  # 'left' -> 'L'
FOLLOW_BUTTON = {'left': BUTTON_LEFT, 'right': BUTTON_RIGHT}
UNFAMILIAR = 'assist holding: unfamiliar motion'
STOPPED_TEXT = 'assist stopped: press Start assist to resume'

# What the node publishes: AssistTarget's fields (positions rad, puppet joint order) ...
Target = collections.namedtuple('Target', 'side positions gripper_closed confidence hold detail')
# ... AssistState's ...
Status = collections.namedtuple('Status', 'state leader follower task method confidence detail')
# ... and what one step publishes: target (None before the first prediction), leader_pose and
# ghost (7 angles of the leader's measured and the follower's predicted pose, for the ghost;
# None when not due or unknown), state (a Status), publish_state (changed, or due), warning
# ('' or what went wrong with the model's prediction).
Step = collections.namedtuple('Step', 'target leader_pose ghost state publish_state warning')


def arm_positions(names, positions, side):
    """Return Baxter arm side's 7 angles (rad, puppet joint order) from a JointState's fields.

    Raises:
        ValueError: names and positions differ in number, or a joint of the arm is missing.
    """
    if len(names) != len(positions):
        raise ValueError('%d names but %d positions' % (len(names), len(positions)))
    position = dict(zip(names, positions))
    missing = [n for n in arm_joint_names(side) if n not in position]
    if missing:
        raise ValueError('no %s' % ', '.join(missing))
    return [float(position[n]) for n in arm_joint_names(side)]


def check_prediction(prediction):
    """Return (7 float angles, gripper closed, confidence 0..1, familiar) of a Prediction.

    Raises:
        ValueError: not 7 finite angles, or a confidence that is not a number in 0..1.
    """
    positions = [float(p) for p in prediction.positions]
    confidence = float(prediction.confidence)
    if len(positions) != 7 or not all(math.isfinite(p) for p in positions):
        raise ValueError('a prediction needs 7 finite angles, got %r' % (positions,))
    if not 0.0 <= confidence <= 1.0:
        raise ValueError('a confidence must be in 0..1, got %r' % confidence)
    return positions, bool(prediction.gripper_closed), confidence, bool(prediction.familiar)


class AssistCore:
    """Decide the assisted arm's target, its ghost and the assist's state from the inputs.

    Args:
        predictor: a model_file Predictor (leader, follower, task, method, reset(), step(t,
            leader_positions) -> Prediction), or None before a model is loaded.
        rate_hz: how often step() is called (the ghost is due every few steps).
        leader_timeout_s: a leader pose older than this holds the assisted arm.
        resume_after_s: familiar predictions for this long end a hold for unfamiliar motion.
        problem: the state's detail while there is no predictor.
    """

    def __init__(self, predictor, rate_hz=100.0, leader_timeout_s=LEADER_TIMEOUT_S, resume_after_s=0.3,
                 problem='no model yet'):
        if not (rate_hz > 0.0 and leader_timeout_s > 0.0 and resume_after_s >= 0.0):
            raise ValueError('rate, leader timeout and resume time must be positive, got '
                             '%r, %r, %r' % (rate_hz, leader_timeout_s, resume_after_s))
        self._ghost_every = max(1, int(round(rate_hz / GHOST_RATE_HZ)))
        self._leader_timeout_s, self._resume_after_s = leader_timeout_s, resume_after_s
        self._predictor, self._problem = None, problem
        self._pose = self._pose_t = None     # the newest valid leader pose and its time
        self._stepped_t = None               # time of the pose the predictor saw last
        self._prediction = None              # (positions, gripper_closed) newest valid
        self._confidence = 0.0
        self._unfamiliar_hold, self._familiar_since = True, None
        self._hold_text = ''                 # why the motion holds: unfamiliar or starting
        self._stopped = self._engaged = False
        self._steps = 0
        self._sent = None                    # (key fields, confidence, time) last published
        if predictor is not None:
            self.on_model(0.0, predictor)

    @property
    def predictor(self):
        """The Predictor in use, or None."""
        return self._predictor

    def on_model(self, t, predictor, problem=''):
        """Take a loaded Predictor, or None and the problem (why there is none) at time t (s).

        Returns:
            '' or why the predictor is refused (its sides), then counted as no predictor.
        """
        del t  # the state says it at the next step
        if predictor is not None and not (
                predictor.leader in BAXTER_SIDES and predictor.follower in BAXTER_SIDES and
                predictor.leader != predictor.follower):
            problem = 'the model names leader %r and follower %r: not Baxter\'s two arms' % (
                predictor.leader, predictor.follower)
            predictor = None
        self._predictor, self._problem = predictor, problem
        self._restart()
        return problem if predictor is None else ''

    def on_leader_pose(self, t, positions):
        """Take the leader arm's 7 measured angles (rad) at time t (s).

        Returns:
            '' or a warning: the pose was refused (not 7 finite angles) and not used.
        """
        try:
            angles = [float(a) for a in positions]
        except (TypeError, ValueError):
            return 'leader pose refused: not numbers: %r' % (positions,)
        if len(angles) != 7 or not all(math.isfinite(a) for a in angles):
            return 'leader pose refused: needs 7 finite angles, got %r' % (angles,)
        self._pose, self._pose_t = angles, t
        return ''

    def on_command(self, t, text):
        """Take a command of the GUI at time t (s): 'stop' or 'start'.

        Returns:
            '' or a warning: the text is no command (ignored).
        """
        del t
        if text not in ASSIST_COMMANDS:
            return 'assist command %r ignored: not one of %s' % (text, ', '.join(ASSIST_COMMANDS))
        self._stopped = text == 'stop'
        return ''

    def on_teleop_state(self, t, assist_follower):
        """Take whether the leader's arm controller drives the assisted arm from the assist."""
        del t
        self._engaged = bool(assist_follower)

    def step(self, t):
        """Return the Step of time t (s): what to publish."""
        self._steps += 1
        warning = ''
        current = self._pose_t is not None and t - self._pose_t <= self._leader_timeout_s
        if self._predictor is not None and current and self._pose_t != self._stepped_t:
            warning = self._predict()
        elif self._predictor is not None and not current and self._stepped_t is not None:
            self._restart(keep_pose=True)  # a gap in the motion: the predictor starts afresh
        state, detail, hold = self._decide(current)
        target = leader_pose = ghost = None
        if self._prediction is not None:
            positions, closed = self._prediction
            target = Target(self._predictor.follower, positions, closed, self._confidence,
                            hold, detail if hold else '')
            if self._steps % self._ghost_every == 0:
                ghost, leader_pose = positions, self._pose
        status = self._status(state, detail)
        return Step(target, leader_pose, ghost, status, self._due(t, status), warning)

    def _restart(self, keep_pose=False):
        """Reset the predictor and hold until familiar; keep_pose: the hold target keeps the
        newest prediction's pose (else none is sent until the next prediction)."""
        if self._predictor is not None:
            self._predictor.reset()
        self._stepped_t = None
        if not keep_pose:
            self._prediction = None
        self._confidence = 0.0
        self._unfamiliar_hold, self._familiar_since = True, None
        self._hold_text = ''

    def _predict(self):
        """Step the predictor with the newest pose; return '' or what went wrong."""
        self._stepped_t = self._pose_t
        try:
            positions, closed, confidence, familiar = check_prediction(
                self._predictor.step(self._pose_t, list(self._pose)))
        except Exception as error:  # pylint: disable=broad-except  (any model failure holds)
            self._confidence, self._unfamiliar_hold, self._familiar_since = 0.0, True, None
            self._hold_text = 'assist holding: the model failed'
            return 'the model failed on a leader pose: %s: %s' % (type(error).__name__, error)
        self._prediction, self._confidence = (positions, closed), confidence
        if not familiar:
            self._unfamiliar_hold, self._familiar_since = True, None
            self._hold_text = UNFAMILIAR
            return ''
        if self._familiar_since is None:
            self._familiar_since = self._pose_t
        if self._pose_t - self._familiar_since >= self._resume_after_s:
            self._unfamiliar_hold, self._hold_text = False, ''
        return ''

    def _decide(self, current):
        """Return (state, detail, hold) of now."""
        predictor = self._predictor
        if predictor is None:
            return OFF, 'assist off: %s' % self._problem, True
        leader, follower = predictor.leader, predictor.follower
        if self._stopped:
            return STOPPED, STOPPED_TEXT, True
        if not current:
            what = 'not current' if self._pose_t is not None else 'not known yet'
            return HOLDING, "assist holding: Baxter's %s arm's pose is %s" % (leader, what), True
        if self._unfamiliar_hold:
            return HOLDING, self._hold_text or (
                "assist holding: watching the %s arm's motion first" % leader), True
        if self._engaged:
            return ASSISTING, ("assisting Baxter's %s arm from the %s arm's motion; take over: "
                               'press %d on puppet %s' % (follower, leader,
                                                          FOLLOW_BUTTON[follower],
                                                          PUPPET_OF[follower])), False
        return READY, ("ready: press %d on puppet %s to let the assist drive Baxter's %s arm"
                       % (FOLLOW_BUTTON[follower], PUPPET_OF[leader], follower)), False

    def _status(self, state, detail):
        predictor = self._predictor
        if predictor is None:
            return Status(state, '', '', '', '', 0.0, detail)
        return Status(state, predictor.leader, predictor.follower, str(predictor.task),
                      str(predictor.method), self._confidence, detail)

    def _due(self, t, status):
        """Return whether the state goes out now (and note it as sent)."""
        key = status[:5] + status[6:]
        sent = self._sent
        due = (sent is None or key != sent[0] or t - sent[2] >= STATE_PERIOD_S or
               (abs(status.confidence - sent[1]) >= CONFIDENCE_STEP and
                t - sent[2] >= CONFIDENCE_PERIOD_S))
        if due:
            self._sent = (key, status.confidence, t)
        return due
