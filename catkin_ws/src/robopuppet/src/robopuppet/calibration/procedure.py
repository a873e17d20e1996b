"""The calibration procedure's steps, shared by the GUI wizard and the terminal command.

Pure: no ROS, no Qt, no clock. Angles in rad; `stored` is {joint: {setting name: value}} as
config_X stores it (the settings loaded in the puppet); a joint's reading is (encoder status
text, reported angle rad).

Steps: every quadrature joint Working (joints_to_turn), then one capture per pose of POSES
(Session.capture turns the reported angles back into raw encoder angles with the stored
settings), then solve (solver.solve) and the old and new values side by side (Session.changes),
then apply_changes (one all-or-none set_arm_config request for every joint: config_X stores
all of them with one file replace, or none), and undo with the old values the same way.
DirectionCheck then asks for each joint to be moved in Baxter's positive direction.

While a pose is awaited, the wizard and the command publish it on interface.CALIBRATION_TARGET
(target_state) for the calibration target ghost in RViz (ghost/, docs/ghost.md).
"""
import collections
import math

from robopuppet import baxter_description, interface, settings
from robopuppet.calibration import solver

CALIBRATED = ('home_angle', 'sign_angle')
CLAMP_MARGIN_RAD = 0.01  # a reading this close to angle_min/angle_max may be clamped
END_PIECE_PRESSED_BELOW, END_PIECE_RELEASED_ABOVE = 0.3, 0.7  # gripper 3, with hysteresis

Pose = collections.namedtuple('Pose', 'name angles_rad')
# Baxter's zero pose first, then two that move every joint by 0.5 rad (within Baxter's joint
# limits: joint 3, the elbow bend, cannot go below -0.05 rad, so it bends +0.5 rad in both).
POSES = (
    Pose("Baxter's zero pose", (0.0,) * settings.NUM_JOINTS),
    Pose('pose A', (0.5, -0.5, 0.5, 0.5, 0.5, 0.5, 0.5)),
    Pose('pose B', (-0.5, 0.5, -0.5, 0.5, -0.5, -0.5, -0.5)),
)

# Relative to interface.puppet_ns(side): sensor_msgs/JointState, the pose awaited as Baxter's
# joint names and angles (rad) of the arm on the puppet's side; nothing while none is awaited.
TARGET_RATE_HZ = 10.0  # the target ghost drops a target not repeated within 0.5 s

Change = collections.namedtuple('Change', 'joint old new fit')
Change.__doc__ = """One joint's calibration: old and new {'home_angle', 'sign_angle'} and the
solver.JointFit behind new."""
Applied = collections.namedtuple('Applied', 'written error')
Applied.__doc__ = """What apply_changes did: written, the joints stored (in order: every joint of
the request, or none), and error, '' or why nothing was stored."""


class CaptureError(ValueError):
    """A pose cannot be captured now; str() tells the operator what to do."""


def pose_from_words(words):
    """Return the Pose named or typed in words (a list of strings), or raise ValueError.

    A name of POSES, case and spaces ignored ("pose A", "posea", "a", "zero" for Baxter's zero
    pose), or seven angles in rad.
    """
    text = ''.join(words).lower().replace("'", '')
    for pose in POSES:
        key = pose.name.lower().replace("'", '').replace(' ', '')
        if text in (key, key.replace('pose', ''), 'zero' if pose is POSES[0] else key):
            return pose
    try:
        angles = [float(w) for w in words]
    except ValueError:
        angles = None
    if angles is None or len(angles) != settings.NUM_JOINTS:
        raise ValueError('not a pose: %r (a name: %s, or %d angles in rad)' % (
            ' '.join(words), ', '.join(repr(p.name) for p in POSES), settings.NUM_JOINTS))
    if not all(math.isfinite(a) and abs(a) <= math.pi for a in angles):
        raise ValueError('every angle must be a number within [-pi, pi] rad')
    return Pose('typed pose', tuple(angles))


def readout(readings):
    """Return the reported angles of every joint as one line (rad; '  —  ' where none)."""
    return ' '.join('%+.2f' % a if math.isfinite(a) else '  —  ' for _, a in readings)


def joints_to_turn(readings):
    """Return the quadrature joints that are not Working (to turn through their index mark)."""
    return [j for j in settings.QUAD_JOINTS if readings[j][0] != interface.WORKING]


def target_state(side, pose):
    """Return (names, positions) of interface.CALIBRATION_TARGET for a Pose on puppet side:
    Baxter's joint names of the arm that copies that puppet arm, and the pose's angles (rad)."""
    return (baxter_description.arm_joint_names(interface.BAXTER_SIDE[interface.check_side(side)]),
            list(pose.angles_rad))


def raw_angles(readings, stored):
    """Return the seven raw encoder angles behind the readings, or raise CaptureError.

    Refused: a joint not Working, a reading that is not a number, a reading within
    CLAMP_MARGIN_RAD of angle_min or angle_max (the firmware clamps there, so the raw angle
    cannot be recovered), and no stored settings.
    """
    if stored is None:
        raise CaptureError('no stored settings from config_X yet: is the config node running?')
    problems, raws = [], []
    for joint, (status, angle) in enumerate(readings):
        cfg = stored[joint]
        if status != interface.WORKING:
            problems.append('joint %d is %s' % (joint, status or 'not reporting'))
        elif not math.isfinite(angle):
            problems.append('joint %d reports no angle' % joint)
        elif min(abs(angle - cfg['angle_min']), abs(angle - cfg['angle_max'])) < CLAMP_MARGIN_RAD:
            problems.append('joint %d reads %.3f rad, at its limit [%.3f, %.3f]: the reading '
                            'may be clamped (widen angle_min/angle_max, then capture again)'
                            % (joint, angle, cfg['angle_min'], cfg['angle_max']))
        else:
            raws.append(solver.raw_from_reported(angle, cfg['home_angle'], cfg['sign_angle']))
    if problems:
        raise CaptureError('cannot capture: ' + '; '.join(problems))
    return raws


class Session:
    """The captures of one calibration run, one per pose of `poses`, in order."""

    def __init__(self, poses=POSES):
        self.poses = tuple(poses)
        self.raws = []  # per captured pose, seven raw encoder angles (rad)

    def pose(self):
        """Return the pose to capture next, or None when every pose is captured."""
        return self.poses[len(self.raws)] if len(self.raws) < len(self.poses) else None

    def capture(self, readings, stored):
        """Capture the next pose from the readings and the stored settings (CaptureError)."""
        if self.pose() is None:
            raise CaptureError('every pose is captured already')
        self.raws.append(raw_angles(readings, stored))

    def retake(self):
        """Forget the last capture (nothing happens before the first)."""
        if self.raws:
            self.raws.pop()

    def fits(self):
        """Return the solver.JointFit of each joint (SolveError before every pose)."""
        if self.pose() is not None:
            raise solver.SolveError('%d of %d poses captured' % (len(self.raws), len(self.poses)))
        return solver.solve([pose.angles_rad for pose in self.poses], self.raws)

    def changes(self, stored):
        """Return a Change per joint: stored values beside the solution."""
        return [Change(fit.joint, {n: stored[fit.joint][n] for n in CALIBRATED},
                       {'home_angle': fit.home_angle, 'sign_angle': fit.sign_angle}, fit)
                for fit in self.fits()]


def changes_table(changes):
    """Return the old and new values of each joint, its residual and any problem, as text."""
    lines = ['joint  home_angle old -> new (rad)  sign_angle old -> new  residual (rad)']
    for c in changes:
        lines.append('%5d  %8.4f -> %8.4f  %+4.0f -> %+4.0f  %8.4f  %s' % (
            c.joint, c.old['home_angle'], c.new['home_angle'], c.old['sign_angle'],
            c.new['sign_angle'], c.fit.residual_rad, c.fit.problem))
    return '\n'.join(lines)


def apply_changes(set_arm_config, values):
    """Store {joint: {name: value}} in one all-or-none request: set_arm_config(values).

    set_arm_config returns an answer with .stored and .error (gui.puppet_client.SetAnswer) or
    raises a RuntimeError (the request may not have reached config_X: it stored all or none).
    Returns an Applied: every joint written, or none and why.
    """
    values = {joint: dict(joint_values) for joint, joint_values in sorted(values.items())}
    try:
        answer = set_arm_config(values)
    except RuntimeError as error:
        return Applied([], str(error))
    if not answer.stored:
        return Applied([], 'refused: %s' % answer.error)
    return Applied(list(values), '')


class EndPiecePress:
    """Tell a press of the end-piece button (gripper 3: ~1 released, ~0 pressed), once each."""

    def __init__(self):
        self._pressed = True  # a button held down when the wizard starts is not a press

    def update(self, reading):
        """Take a reading; return True when it begins a press."""
        if not math.isfinite(reading):
            return False
        if self._pressed:
            self._pressed = reading < END_PIECE_RELEASED_ABOVE
            return False
        self._pressed = reading < END_PIECE_PRESSED_BELOW
        return self._pressed


class DirectionCheck:
    """Ask for each joint in turn to be moved in Baxter's positive direction; note which way.

    update(readings) takes the reported angles: the first reading of a joint is its start, and
    once it has moved move_rad either way the result is kept and the next joint's turn begins.
    """

    def __init__(self, joints=settings.JOINTS, move_rad=0.2):
        self.joints = tuple(joints)
        self.move_rad = move_rad
        self.moved_positive = {}  # joint -> True when it moved the right way
        self._start_rad = None

    def joint(self):
        """Return the joint to move now, or None when every joint is checked."""
        return next((j for j in self.joints if j not in self.moved_positive), None)

    def update(self, angles_rad):
        """Take the reported angles (rad); return the joint just checked, or None."""
        joint = self.joint()
        if joint is None or not math.isfinite(angles_rad[joint]):
            return None
        if self._start_rad is None:
            self._start_rad = angles_rad[joint]
            return None
        moved = solver.wrap(angles_rad[joint] - self._start_rad)
        if abs(moved) < self.move_rad:
            return None
        self.moved_positive[joint] = moved > 0.0
        self._start_rad = None
        return joint

    def wrong(self):
        """Return the joints that moved the wrong way."""
        return [j for j, right in sorted(self.moved_positive.items()) if not right]
