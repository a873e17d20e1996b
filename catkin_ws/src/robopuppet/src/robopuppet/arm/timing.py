"""How long arm_X waits for the puppet's joint states before it counts the puppet silent (pure).

The puppet sends a state set every 1 / comm_rate seconds. The state timeout spans STALL_PERIODS
such periods, so that jitter and a stall of one to three sets never trip it, and at least
MIN_STATE_TIMEOUT_S, the host's own scheduling jitter whatever the rate. A puppet that goes
silent (no state sets and no heartbeats) stops Baxter following after the state timeout (or the
heartbeat timeout, if shorter) plus STOP_AFTER_TIMEOUT_S.

At 10 Hz and above that stop comes within interface.STOP_WITHIN_S (0.5 s). Below 10 Hz both
cannot hold (at 2 Hz one period alone is 0.5 s): the timeout keeps its margin, since a controller
that faults between normal state sets stops Baxter at random and is of no use, and the stop takes
longer; StateTimeout.describe() says by how much, and arm_X logs it and shows it in /diagnostics.

With the puppet on another host (two rooms, one network) a stream can also arrive steadily but
late. arm_X therefore also bounds the age of each puppet sample on arrival, measured on the
robot clock as an upper bound: the estimate plus the operator clock offset's error bound (half
the shortest recent round trip, robopuppet.arm.link_clock), so that an uncertain clock makes
samples look older, never younger. An older sample is late: it is dropped (never used for a
command, counted and reported), and only usable samples count against the state timeout, so
the stream is stale, a silent puppet, when no usable sample came for the state timeout; the
fault then names the newest late sample's age and the bound. The default,
DEFAULT_MAX_SAMPLE_AGE_S = 0.35 s, is reasoned out as follows:

- Baxter never follows a sample more than 0.5 s late (interface.STOP_WITHIN_S): a used sample
  is at most 0.35 s old on arrival, arm_X handles it within HANDLING_MARGIN_S (0.05 s: its
  callback queue on a loaded host) and it reaches Baxter by the next command step at the latest
  (STOP_AFTER_TIMEOUT_S, 0.1 s). A link that fails stops Baxter within 0.5 s of the newest
  usable sample: no usable sample for the state timeout (0.4 s at 10 Hz) is silence, whether
  nothing arrives or only late samples do.
- A working link passes: at 50 ms one way a sample's age bound is about 0.1 s (the delay plus
  half the 0.1 s round trip). ROS carries the samples over TCP, so a lost packet is a late
  sample, not a missing one: on a path with 1 % loss TCP resends it after the next sample's
  acknowledgement, a tail-loss probe or Linux's minimum retransmission timeout, and the samples
  behind it wait; at 10 Hz on a 50 ms path the held sample arrives about 0.3 s old, up to
  0.45 s on a loaded host, the next one with it, 0.1 s younger. Refusing such a sample used to
  fault the teleop every few seconds; dropping it costs Baxter one state period of the hand,
  and the sample behind it is used. At 10 Hz the gap between usable samples is then about the
  held sample's age, so a hold-up of up to the state timeout passes; a longer one (two
  retransmissions, or the machine stalling as well) is silence: on the safe side.
- No fault on a count of consecutive late samples: a steadily late stream leaves no usable
  sample, so the state timeout ends it 0.4 s after the last usable one at 10 Hz (within the
  0.5 s stop), at most a state period after a count of even 3 late samples would; and at faster
  rates a retransmission delivers a burst of held samples at once, several of them late, which
  such a count would fault on although usable ones follow in the same burst.
- On the robot host the bound does not depend on comm_rate: a sample's age is counted from its
  stamp to its arrival, not across the gap to the next one (the state timeout covers gaps).
"""
import collections
import math

from robopuppet.interface import DEFAULT_COMM_RATE_HZ, HEARTBEAT_TIMEOUT_S, STOP_WITHIN_S

STALL_PERIODS = 4            # the newest set's own period plus three sets late or missing
MIN_STATE_TIMEOUT_S = 0.2    # scheduling jitter of the serial and arm nodes on a loaded host
# From silence detected to Baxter holding still: the next command step (at most one period of
# the slowest allowed command rate, 10 Hz) sends the stay command, Baxter takes it at once.
STOP_AFTER_TIMEOUT_S = 0.1
# From a puppet sample's arrival to arm_X acting on it: its callback queue on a loaded host.
HANDLING_MARGIN_S = 0.05
DEFAULT_MAX_SAMPLE_AGE_S = round(STOP_WITHIN_S - STOP_AFTER_TIMEOUT_S - HANDLING_MARGIN_S, 6)


class StateTimeout(collections.namedtuple('StateTimeout', 'comm_rate_hz timeout_s stop_s')):
    """The state timeout at a state-set rate.

    Fields:
        comm_rate_hz: the puppet's state-set rate (Hz).
        timeout_s: the puppet is silent after this long without joint states (s).
        stop_s: a puppet that goes silent stops Baxter following within this time (s).
    """

    __slots__ = ()

    @property
    def meets_stop(self):
        """Return whether a silent puppet stops Baxter within interface.STOP_WITHIN_S."""
        return self.stop_s <= STOP_WITHIN_S + 1e-9

    def describe(self):
        """Return what the timeout means at this rate; it says so when the stop comes late."""
        if self.meets_stop:
            return ('state timeout %.2f s at comm_rate %g Hz: a silent puppet stops Baxter within '
                    '%.2f s' % (self.timeout_s, self.comm_rate_hz, self.stop_s))
        return ('at comm_rate %g Hz a silent puppet stops Baxter only after %.2f s, not within '
                '%.2f s: the state timeout is %.2f s (%d state periods) so that normal state '
                'sets never trip it; %g Hz or more meets %.2f s' % (
                    self.comm_rate_hz, self.stop_s, STOP_WITHIN_S, self.timeout_s,
                    STALL_PERIODS, lowest_rate_meeting_stop_hz(), STOP_WITHIN_S))


def state_timeout(comm_rate_hz):
    """Return the StateTimeout for state sets at comm_rate_hz (Hz).

    Raises:
        ValueError: comm_rate_hz is not a finite positive number.
    """
    if not (math.isfinite(comm_rate_hz) and comm_rate_hz > 0.0):
        raise ValueError('comm_rate must be a positive number of Hz, got %r' % (comm_rate_hz,))
    timeout_s = max(STALL_PERIODS / comm_rate_hz, MIN_STATE_TIMEOUT_S)
    stop_s = min(timeout_s, HEARTBEAT_TIMEOUT_S) + STOP_AFTER_TIMEOUT_S
    return StateTimeout(float(comm_rate_hz), timeout_s, stop_s)


def lowest_rate_meeting_stop_hz():
    """Return the lowest state-set rate (Hz) at which a silent puppet stops Baxter in time."""
    return STALL_PERIODS / (STOP_WITHIN_S - STOP_AFTER_TIMEOUT_S)


DEFAULT = state_timeout(DEFAULT_COMM_RATE_HZ)  # at the 2020 firmware's 10 Hz: 0.4 s


class AgeBound(collections.namedtuple('AgeBound', 'bound_s late_s')):
    """The bound on a puppet sample's age on arrival.

    Fields:
        bound_s: an older sample is late: dropped, never used (s).
        late_s: Baxter follows the puppet at most this late: the bound (which counts the
            clock's error), arm_X's handling and a command step (s).
    """

    __slots__ = ()

    @property
    def meets_stop(self):
        """Return whether Baxter follows within interface.STOP_WITHIN_S of the puppet."""
        return self.late_s <= STOP_WITHIN_S + 1e-9

    def describe(self):
        """Return what the bound means; it says so when Baxter may follow too late."""
        text = 'puppet samples older than %.2f s on arrival are dropped: ' % self.bound_s
        if self.meets_stop:
            return text + 'Baxter follows the puppet at most %.2f s late' % self.late_s
        return text + 'Baxter may follow the puppet %.2f s late, not within %.2f s' % (
            self.late_s, STOP_WITHIN_S)


def sample_age_bound(max_sample_age_s):
    """Return the AgeBound for ~max_sample_age (s).

    Raises:
        ValueError: it is not a finite positive number.
    """
    if not (math.isfinite(max_sample_age_s) and max_sample_age_s > 0.0):
        raise ValueError('max_sample_age must be a positive number, got %r' % (max_sample_age_s,))
    return AgeBound(float(max_sample_age_s),
                    max_sample_age_s + HANDLING_MARGIN_S + STOP_AFTER_TIMEOUT_S)
