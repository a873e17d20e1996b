"""The rate of /robot/joint_states that /robot/joint_state_publish_rate asks for; when it is due.

A real Baxter publishes its joint states at 100 Hz until a std_msgs/UInt16 on
/robot/joint_state_publish_rate sets another rate (Rethink's API reference: at most 800 Hz).
The SDK asks for more: its wobbler 500 Hz, joint_torque_springs 1000 Hz, the trajectory action
server its control rate (100 Hz by default). The stand-in publishes from one loop at ~rate_hz
(100 Hz), the most it keeps on time on a 2-core machine (docs/baxter_sim.md, benchmarks), so it
takes any rate up to that loop's and publishes at the loop's rate when asked for more; 0 Hz,
which would stop the joint states, is refused. Below the loop's rate, joint states go out on
the cycles when one is due, so their mean rate is the rate asked. Pure: no ROS, no clock.
"""
from robopuppet.baxter_sim.baxter_refusals import CommandError

DEFAULT_RATE_HZ = 100.0    # a real Baxter's rate after power-up
BAXTER_MAX_RATE_HZ = 800.0


class JointStateRate:
    """Decide the joint states' rate and which cycles publish them.

    Args:
        loop_rate_hz: the publishing loop's rate (Hz), the most the stand-in publishes at.
    """

    def __init__(self, loop_rate_hz):
        self.loop_rate_hz = float(loop_rate_hz)
        self.rate_hz = min(DEFAULT_RATE_HZ, self.loop_rate_hz)
        self._next_s = None

    def request(self, asked_hz):
        """Take a joint_state_publish_rate; return the log line saying the rate now published.

        Raises:
            CommandError: 0 Hz (reason 'zero rate'), or more than the loop can (reason
                'too fast': the rate is then the loop's, and the message says so).
        """
        asked_hz = int(asked_hz)
        if asked_hz <= 0:
            raise CommandError('joint state publish rate %d Hz ignored: it would stop '
                               '/robot/joint_states; still %g Hz' % (asked_hz, self.rate_hz),
                               'zero rate')
        self.rate_hz = min(float(asked_hz), self.loop_rate_hz)
        self._next_s = None
        if asked_hz > self.loop_rate_hz:
            raise CommandError(
                'joint state publish rate %d Hz asked: the stand-in publishes /robot/joint_states'
                ' at %g Hz, the most its loop does on this machine (a real Baxter: up to %g Hz)'
                % (asked_hz, self.rate_hz, BAXTER_MAX_RATE_HZ), 'too fast')
        return '/robot/joint_states now published at %g Hz, as asked' % self.rate_hz

    def due(self, now_s):
        """Return whether the cycle at now_s (s) publishes joint states; each call is a cycle."""
        if self.rate_hz >= self.loop_rate_hz:
            return True
        # Half a loop period of slack: a cycle a little early still counts as on time.
        slack_s = 0.5 / self.loop_rate_hz
        if self._next_s is None or now_s + slack_s >= self._next_s:
            period_s = 1.0 / self.rate_hz
            start = now_s if self._next_s is None or now_s - self._next_s > period_s \
                else self._next_s
            self._next_s = start + period_s
            return True
        return False
