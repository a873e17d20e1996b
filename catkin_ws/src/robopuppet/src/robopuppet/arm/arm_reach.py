"""Where one Baxter arm can be until its next command takes effect (pure, time as an argument).

The model of Baxter's joint position controller that keep-out zones rely on (docs/zones.md):
each joint moves from where it is toward its newest target, never past it, and holds where it
is when commands stop; a command takes effect within COMMAND_DELAY_S of being sent. So from a
pose measured at t_m on, the arm stays inside the box (joint by joint, the smallest and largest
angle) of that pose, the target in force at t_m (at worst the newest command sent by
t_m - COMMAND_DELAY_S) and every command sent since; the next command stretches the box to
hold it too. Without commands of ours in that window (following has just started, or another
node commands the arm) the measured velocity extends the pose for the measurement's age.
"""
import collections

import numpy as np

COMMAND_DELAY_S = 0.03   # a command reaches Baxter's controller this soon at the latest
HISTORY_S = 2.0          # commands older than this (s) are forgotten (keep > any delay)


class ArmReach:
    """Keep the commands sent to one arm and say where the arm can be.

    Args:
        delay_s: how late a command may reach Baxter's controller at most (s).
    """

    def __init__(self, delay_s=COMMAND_DELAY_S):
        self.delay_s = delay_s
        self._sent = collections.deque()   # (t s, (7,) angles rad), oldest first
        self._forgot = False               # whether older commands were forgotten
        self.box = None                    # (lo, hi) of the last box(): where the arm can be

    def sent(self, t, command):
        """Take that `command` (7 rad) was sent at time t (s)."""
        self._sent.append((t, np.asarray(command, np.float64)))
        while len(self._sent) > 1 and self._sent[1][0] < t - HISTORY_S:
            self._sent.popleft()
            self._forgot = True

    def where(self, t, measured_t, pose, velocities=None):
        """Return (lo, hi), (7,) each: the box the arm is in from now until a command sent at
        t (s) takes effect, from its pose (7 rad) measured at measured_t and, where no command
        of ours is known in that window, its velocities (7 rad/s); None when the pose is older
        than the commands remembered (HISTORY_S): the target then in force is not known."""
        pose = np.asarray(pose, np.float64)
        since = measured_t - self.delay_s
        if self._forgot and self._sent[0][0] > since:
            return None
        window = [q for sent_t, q in self._sent if sent_t > since]
        earlier = [q for sent_t, q in self._sent if sent_t <= since]
        if earlier:
            window.append(earlier[-1])
        if window:
            points = np.vstack([pose] + window)
        else:
            ahead = pose + np.asarray(velocities if velocities is not None else np.zeros(7),
                                      np.float64) * max(t - measured_t + self.delay_s, 0.0)
            points = np.vstack([pose, ahead])
        self.box = points.min(axis=0), points.max(axis=0)
        return self.box

    def inside(self, angles):
        """Return angles (7 rad) moved into the last box (unchanged before the first box)."""
        if self.box is None:
            return list(angles)
        return list(np.clip(angles, *self.box))
