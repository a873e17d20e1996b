"""What the two episode players share: step the core at its rate, send each Step, know when to
exit, and say how far the episode has played.

The ROS side of robopuppet.episodes.robot_player's RobotPlayer (onto Baxter) and
robopuppet.episodes.puppet_player's PuppetPlayer (into the puppet); both cores (replay.Replay,
puppet_playback.PuppetPlayback) play an episode forward in time at a speed factor, stop on their
stop rules and report their phase, why and progress() alike.
"""
import threading
import time

import rospy

from robopuppet.episodes import replay
from robopuppet.periodic import Guard, Loop

STAY_S = 0.3  # after a stop the stay commands go on this long (over the puppet's button 1)


class Player:
    """Base of the episode players: a subclass sends a core's Step in _send(step).

    Args:
        core: the pure player (replay.Replay or puppet_playback.PuppetPlayback), called only
            under the lock with time.monotonic() first (_call).
        say(text): tells the operator (the terminal).
    Attributes:
        done: set once the episode finished, or STAY_S after it stopped.
    """

    def __init__(self, core, say):
        self.core, self._say, self._lock = core, say, threading.Lock()
        self.done = threading.Event()
        self._stopped_t = None

    def _call(self, method, *args):
        with self._lock:
            return method(time.monotonic(), *args)

    def _send(self, step):
        raise NotImplementedError

    def _tick(self):
        with self._lock:
            now = time.monotonic()
            step = self.core.step(now)
            self._send(step)
        if step.phase == replay.STOPPED:
            self._stopped_t = self._stopped_t or now
            if now - self._stopped_t >= STAY_S:
                self.done.set()
        elif step.phase == replay.FINISHED:
            self.done.set()

    def _play(self, what, rate_hz, report_s):
        """Tick at rate_hz on a Loop named `what` until done or shutdown; say the seconds played
        (once a second of the episode, looked at every report_s)."""
        loop = Loop(Guard('replay', rospy.logerr), what, 1.0 / rate_hz, self._tick).start()
        shown = None
        while not self.done.wait(report_s) and not rospy.is_shutdown():
            played_s, total_s = self.core.progress()
            if self.core.phase == replay.PLAY and int(played_s) != shown:
                self._say('playing %.1f of %.1f s' % (played_s, total_s))
                shown = int(played_s)
        loop.stop()
