"""Each arm's collision avoidance and cuff interaction, and their suppression, as the stand-in
models them.

Pure: no rospy, no messages; times are `now_s` (ROS time, s) given by the caller.

Baxter (Rethink SDK 1.2) keeps a safety behaviour suppressed only while an std_msgs/Empty keeps
coming on `/robot/limb/<side>/suppress_<behaviour>` faster than 5 Hz (the SDK wiki's Zero-G
page says so of the cuff; the stand-in takes the same for collision avoidance, which SDK 1.2.0's
tuck_arms.py suppresses at 20 Hz): each message suppresses it for SUPPRESS_TIMEOUT_S.

- Collision avoidance keeps an arm's links (collision blocks slightly larger than each link) off
  the other arm and Baxter's own body, and names what it avoids in CollisionAvoidanceState
  (`other_arm`, `collision_object`). The stand-in does not model the arms against each other or
  the body, so nothing is avoided: the state is always (False, []), suppressed or not. Its
  obstacles are not the body: contact with them is what Baxter's collision *detection* (impact,
  squish) reacts to, another topic. Suppression is kept, and logged, so that it is visible.
- Cuff interaction: squeezing the cuff (`<side>_lower_cuff`) puts the enabled arm in zero-g:
  its joint controllers let go and nothing the SDK commands moves it. The stand-in has no hand
  to move the arm, so in zero-g the arm holds where it is and joint commands are refused
  ('zero-g'). Suppressed, a squeeze does nothing to the arm (the input still reads pressed).
"""
from robopuppet import interface
from robopuppet.baxter_sim.baxter_refusals import CommandError
from robopuppet.interface import BAXTER_SIDES

SUPPRESS_TIMEOUT_S = 0.2   # one message suppresses for this long (the SDK asks for > 5 Hz)
BEHAVIOURS = ('collision_avoidance', 'cuff_interaction')  # suppress_<behaviour> topics


def cuff_input(side):
    """Return the digital input name of an arm's cuff squeeze ('left_lower_cuff')."""
    return '%s_lower_cuff' % side


def collision_avoidance_state():
    """Return the CollisionAvoidanceState fields (but the header): nothing avoided."""
    return dict(other_arm=False, collision_object=[])


class Suppression:
    """One safety behaviour of one arm, suppressed for SUPPRESS_TIMEOUT_S after each message."""

    def __init__(self, timeout_s=SUPPRESS_TIMEOUT_S):
        self.timeout_s = timeout_s
        self.last_s = None

    def message(self, now_s):
        """A suppress message arrived at now_s."""
        self.last_s = now_s if self.last_s is None else max(self.last_s, now_s)

    def active(self, now_s):
        """Return whether the behaviour is suppressed at now_s."""
        return self.last_s is not None and now_s - self.last_s <= self.timeout_s


class ArmSafety:
    """One arm's suppressions and zero-g, and the log lines of their changes."""

    def __init__(self, side, timeout_s=SUPPRESS_TIMEOUT_S):
        self.side = side
        self.timeout_s = timeout_s
        self.suppressions = {name: Suppression(timeout_s) for name in BEHAVIOURS}
        self._shown = dict.fromkeys(BEHAVIOURS + ('zero-g',), False)

    def suppress(self, behaviour, now_s):
        """A message on suppress_<behaviour> arrived at now_s."""
        self.suppressions[behaviour].message(now_s)

    def zero_g(self, enabled, cuff_pressed, now_s):
        """Return whether the arm is in zero-g: enabled, cuff squeezed, interaction not
        suppressed."""
        return (enabled and cuff_pressed
                and not self.suppressions['cuff_interaction'].active(now_s))

    def check_command(self, enabled, cuff_pressed, now_s):
        """Raise CommandError ('zero-g') when the arm is in zero-g and cannot take a command."""
        if self.zero_g(enabled, cuff_pressed, now_s):
            raise CommandError('joint command for the %s arm ignored: zero-g, its cuff is '
                               'squeezed (suppress_cuff_interaction to keep control)'
                               % self.side, 'zero-g')

    def changes(self, enabled, cuff_pressed, now_s):
        """Return the log lines of what changed since the last call (suppressions started or
        lapsed, zero-g entered or left)."""
        now = {name: s.active(now_s) for name, s in self.suppressions.items()}
        now['zero-g'] = self.zero_g(enabled, cuff_pressed, now_s)
        lines = []
        for name, on in now.items():
            if on != self._shown[name]:
                lines.append(self._line(name, on))
        self._shown = now
        return lines

    def _line(self, name, on):
        arm = '%s arm: ' % self.side
        if name == 'zero-g':
            return arm + ('zero-g: cuff squeezed; the arm holds and joint commands are refused'
                          if on else 'zero-g ended: joint commands are obeyed again')
        what = name.replace('_', ' ')
        if not on:
            return arm + '%s suppression lapsed (no message for %g s)' % (what, self.timeout_s)
        if name == 'cuff_interaction':
            return arm + 'cuff interaction suppressed: a squeeze does not give zero-g'
        return arm + ('collision avoidance suppressed (the stand-in models no self-collision: '
                      'nothing to avoid either way)')


class RobotSafety:
    """Both arms' ArmSafety, read against a baxter_model.BaxterModel (its enable state and cuff
    inputs) by BaxterApi."""

    def __init__(self, timeout_s=SUPPRESS_TIMEOUT_S):
        self.arms = {side: ArmSafety(side, timeout_s) for side in BAXTER_SIDES}

    def suppress(self, side, behaviour, now_s):
        """A message on an arm's suppress_<behaviour> arrived at now_s."""
        self.arms[side].suppress(behaviour, now_s)

    def joint_command(self, model, side, mode, names, values, now_s):
        """Apply a JointCommand to the model unless the arm is in zero-g.

        Raises:
            CommandError: 'zero-g', or what model.joint_command raises.
        """
        if side in self.arms:
            self.arms[side].check_command(model.enabled, _cuff(model, side), now_s)
        model.joint_command(side, mode, names, values, now_s)

    def hold_zero_g(self, model, now_s):
        """Hold each arm in zero-g where it is (call before model.step)."""
        for side, arm in self.arms.items():
            if arm.zero_g(model.enabled, _cuff(model, side), now_s):
                model.arms[side].hold()

    def changes(self, model, now_s):
        """Return the log lines of both arms' changes since the last call."""
        return [line for side, arm in self.arms.items()
                for line in arm.changes(model.enabled, _cuff(model, side), now_s)]

    def states(self):
        """Return {topic: CollisionAvoidanceState fields but the header} of both arms."""
        return {interface.collision_avoidance_state_topic(side): collision_avoidance_state()
                for side in self.arms}


def _cuff(model, side):
    return model.io.states[cuff_input(side)]
