"""What one puppet arm's stream tells arm_X: its newest valid angles, silence, calibration (pure).

Time is an argument. Teleop asks it whether the puppet has gone silent (no usable joint states
or no heartbeat for too long, or a stale stream: joint states of unknown age since the newest
usable ones), whether data came back after a fault, and which joints keep Baxter from following
(encoders not Working, or no valid angle yet). Joint states that arrive too old are dropped: they
never count as usable, and when no usable ones came for the state timeout the silence is a stale
stream, named with the newest late one's age.
"""
import math

from robopuppet.interface import UNCALIBRATED, WORKING

REFUSED = 'puppet joint states refused'   # how a stale stream's silence begins
STALE = REFUSED + ': stale'                # ... when late ones came but no usable ones


class PuppetWatch:
    """Follow one puppet arm's joint states and heartbeats.

    Args:
        state_timeout_s: the puppet is silent when no usable joint states came for this long.
        heartbeat_timeout_s: ... or no heartbeat for this long (counted from the first joint
            states until the first beat).
    """

    def __init__(self, state_timeout_s, heartbeat_timeout_s):
        self.state_timeout_s = state_timeout_s
        self.heartbeat_timeout_s = heartbeat_timeout_s
        self.refusal = None         # (time, why) of the newest refused joint states
        self._refused = self._stale = self._late = None  # why, since the newest usable ones
        self.angles = None          # newest finite angle per joint (rad), None: never
        self.statuses = []          # newest encoder statuses
        self.state_t = None         # time of the newest joint states, None: never heard from
        self._first_state_t = None
        self._heartbeat_t = None
        self.ignored_angles = 0     # non-finite angles dropped so far

    def on_joint_states(self, t, statuses, angles_rad):
        """Take one set of joint states: 7 status strings and 7 angles (rad).

        A non-finite angle is ignored: the joint keeps its last valid angle, and a joint that
        never sent one counts as not calibrated.
        """
        if self.angles is None:
            self.angles = [None] * len(angles_rad)
        for j, angle in enumerate(angles_rad):
            if math.isfinite(angle):
                self.angles[j] = angle
            else:
                self.ignored_angles += 1
        self.statuses = list(statuses)
        self.state_t = t
        self._refused = self._stale = self._late = None
        if self._first_state_t is None:
            self._first_state_t = t

    def on_refused(self, t, why, stale=False, late=False):
        """Take joint states that may not be used (why: the reason). stale: of unknown age, so
        the stream is stale until usable ones come; late: too old, dropped (the silence they
        leave names them)."""
        self.refusal = (t, why)
        self._refused = why
        if stale:
            self._stale = why
        if late:
            self._late = why

    def on_heartbeat(self, t):
        """Take a heartbeat."""
        self._heartbeat_t = t

    def heartbeat_age(self, t):
        """Return seconds since the last heartbeat, or -1.0 before the first."""
        return -1.0 if self._heartbeat_t is None else t - self._heartbeat_t

    def _heartbeat_ref(self):
        """Return the time the heartbeat timeout counts from: the last beat, else the first data."""
        return self._first_state_t if self._heartbeat_t is None else self._heartbeat_t

    def silent(self, t):
        """Return why the puppet counts as silent at time t, or None (also before any data)."""
        if self.state_t is None:
            return None
        if self._stale:
            return '%s: %s' % (REFUSED, self._stale)
        if t - self.state_t > self.state_timeout_s and self._late:
            return '%s, none usable for %.2f s: the newest %s' % (STALE, t - self.state_t,
                                                                 self._late)
        if t - self.state_t > self.state_timeout_s:
            return 'no joint states from the puppet for %.2f s%s' % (
                t - self.state_t, '; newer ones refused: %s' % self._refused
                if self._refused else '')
        if t - self._heartbeat_ref() > self.heartbeat_timeout_s:
            return 'no heartbeat from the puppet for %.2f s' % (t - self._heartbeat_ref())
        return None

    def fresh_since(self, t0):
        """Return whether both joint states and a heartbeat (or first data) came after t0."""
        return self.state_t is not None and self.state_t > t0 and self._heartbeat_ref() > t0

    def not_calibrated(self):
        """Return which joints keep Baxter from following and what to do, or '' when none."""
        waiting = {}
        for joint, status in enumerate(self.statuses):
            if status != WORKING:
                waiting.setdefault(status, []).append(str(joint))
            elif self.angles[joint] is None:
                waiting.setdefault('with no valid angle yet', []).append(str(joint))
        if not waiting:
            return ''
        return '; '.join(
            'joint%s %s %s' % ('s' if len(joints) > 1 else '', ', '.join(joints), status)
            for status, joints in sorted(waiting.items())) + (
            ': turn each through its index mark' if UNCALIBRATED in waiting else '')
