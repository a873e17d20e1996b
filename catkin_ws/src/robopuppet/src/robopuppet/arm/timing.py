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
"""
import collections
import math

from robopuppet.interface import DEFAULT_COMM_RATE_HZ, HEARTBEAT_TIMEOUT_S, STOP_WITHIN_S

STALL_PERIODS = 4            # the newest set's own period plus three sets late or missing
MIN_STATE_TIMEOUT_S = 0.2    # scheduling jitter of the serial and arm nodes on a loaded host
# From silence detected to Baxter holding still: the next command step (at most one period of
# the slowest allowed command rate, 10 Hz) sends the stay command, Baxter takes it at once.
STOP_AFTER_TIMEOUT_S = 0.1


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
