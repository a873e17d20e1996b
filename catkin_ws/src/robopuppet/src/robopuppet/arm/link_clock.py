"""The operator host's clock as the robot host measures it with pings over ROS (pure).

arm_X (robot host) sends numbered pings (robopuppet_msgs/LinkPing) with `sent` on its own clock;
serial_X (operator host, the node that stamps the puppet's joint states) answers each at once
with `echoed` on its clock. From sent, echoed and the time the echo arrives, as NTP does:

    round trip  rtt    = arrived - sent
    offset      theta  = echoed - (sent + arrived) / 2     (operator clock minus robot clock)

The true offset lies within rtt / 2 of theta whatever the delays of the two directions, so the
echo with the shortest round trip of the last CLOCK_WINDOW is the best estimate, and half its
round trip is the error bound. A puppet sample stamped `stamp` (operator clock) and received at
`now` (robot clock) is then now - (stamp - offset) old, and at most that plus the error bound:
age() returns that upper bound, so a slow link makes samples look older, never younger.

The estimate is trusted (clock_problem() returns '') only while an echo came within
CLOCK_EXPIRY_S: an estimate no ping checks any more could hide a step of the operator clock, so
it expires rather than being trusted forever. An echo whose offset interval does not overlap the
best one's is set aside (counted in `outliers`), not taken: one echo with a forged `echoed` time
must not move the estimate (anyone may publish on link_echo). STEP_CONFIRM such echoes in a row
that agree with each other mean that a clock stepped: they replace the old echoes. From the
second of them until then the offset is in doubt (clock_problem says so: ages are unknown).
An echo answered after more than CLOCK_EXPIRY_S tells nothing current about the clock: it is
ignored (and its ping counts as lost, as every echo after ECHO_TIMEOUT_S does).

A stamp more than PLAUSIBLE_AGE_S old on the estimate is no time a puppet sample was taken
(garbage: 0 < stamp << now): refused as a bad stamp, not aged.

All times are robot-clock seconds (floats) passed in; no rospy, no clock read here.
"""
import collections
import math

from robopuppet.interface import LINK_ECHO

PING_PERIOD_S = 0.1          # 10 Hz: an offset and a loss figure fresh within a state period
ECHO_TIMEOUT_S = 0.5         # a ping not answered within this counts as lost
LOSS_WINDOW_S = 5.0          # the loss is over the pings of this long (those past the timeout)
CLOCK_WINDOW = 50            # the best of the last 50 echoes (5 s at 10 Hz)
CLOCK_EXPIRY_S = 3.0         # no echo for this long: the offset is no longer trusted
CLOCK_STEP_TOLERANCE_S = 0.005  # drift and rounding allowed between consistent echoes
FUTURE_TOLERANCE_S = 0.01    # a sample may look this much younger than 0 beyond the error bound
SENT_TOLERANCE_S = 1e-6      # ROS time's nanoseconds round-trip a float to within this
SEQ_MODULO = 2 ** 32         # LinkPing.seq is a uint32; numbering starts at 1 and skips 0
STEP_CONFIRM = 3             # echoes in a row that show a clock step before it is believed
PLAUSIBLE_AGE_S = 600.0      # an older stamp is garbage, not a sample the network held back

Echo = collections.namedtuple('Echo', 'arrived_s rtt_s offset_s')


class Refused(ValueError):
    """A puppet sample whose age cannot be trusted; str() says why, `kind` names the reason."""

    def __init__(self, kind, why):
        super().__init__(why)
        self.kind = kind


class LinkClock:
    """Number and pace pings, match their echoes, estimate the operator clock and the loss.

    Attributes:
        pings: pings sent so far.
        echoes: echoes taken so far.
        ignored_echoes: echoes ignored (unknown, duplicate, garbage or after the timeout).
        outliers: echoes set aside: they disagreed with the estimate (see STEP_CONFIRM).
        clock_steps: times an echo showed that a clock stepped (the estimate restarted).
        rtt_s: round trip of the newest taken echo (s), None before the first.
    """

    def __init__(self):
        self.pings = self.echoes = self.ignored_echoes = self.clock_steps = self.outliers = 0
        self.rtt_s = None
        self._seq = 0
        self._sent = collections.OrderedDict()   # seq -> [sent_s, arrived_s or None]
        self._window = collections.deque(maxlen=CLOCK_WINDOW)
        self._doubt = []   # the echoes in a row that disagree with the estimate
        self._first_ping_s = self._last_ping_s = self._last_echo_s = None

    # ---- pings and echoes -----------------------------------------------------------------

    def ping(self, now_s):
        """Return (seq, sent_s) of the ping to send now, or None when none is due (pings go
        out every PING_PERIOD_S; a call a little early, from a loop at that period, counts)."""
        if self._last_ping_s is not None and now_s - self._last_ping_s < 0.9 * PING_PERIOD_S:
            return None
        self._seq = self._seq % (SEQ_MODULO - 1) + 1
        self._sent[self._seq] = [now_s, None]
        self._sent.move_to_end(self._seq)
        self._last_ping_s = now_s
        if self._first_ping_s is None:
            self._first_ping_s = now_s
        self.pings += 1
        while self._sent and next(iter(self._sent.values()))[0] < (
                now_s - LOSS_WINDOW_S - 2 * ECHO_TIMEOUT_S):
            self._sent.popitem(last=False)
        return self._seq, now_s

    def on_echo(self, now_s, seq, sent_s, echoed_s):
        """Take an echo that arrived at now_s; return '' or why it was ignored (counted).

        Ignored: a seq not sent (or sent too long ago), one answered already, a `sent` that is
        not the ping's, an `echoed` that is not a positive finite time, an arrival before `sent`,
        an arrival more than CLOCK_EXPIRY_S after `sent` (the ping counts as lost). Set aside
        (counted): one that disagrees with the estimate, until STEP_CONFIRM in a row show that a
        clock stepped.
        """
        why = self._check_echo(now_s, seq, sent_s, echoed_s)
        if why:
            self.ignored_echoes += 1
            return 'link echo ignored (%d so far): %s' % (self.ignored_echoes, why)
        record = self._sent[seq]
        record[1] = now_s
        rtt_s = now_s - record[0]
        if rtt_s > CLOCK_EXPIRY_S:
            self.ignored_echoes += 1
            return ('link echo ignored (%d so far): ping %d answered after %.3f s, longer than an '
                    'estimate is trusted (%g s): counted lost, not used for the clock' % (
                        self.ignored_echoes, seq, rtt_s, CLOCK_EXPIRY_S))
        echo = Echo(now_s, rtt_s, echoed_s - (record[0] + now_s) / 2.0)
        best = self.best()
        if best is not None and not _agree(echo, best):
            if self._doubt and not _agree(echo, min(self._doubt, key=lambda e: e.rtt_s)):
                self._doubt = []   # they disagree among themselves too: garbage, not a step
            self._doubt.append(echo)
            if len(self._doubt) < STEP_CONFIRM:
                self.outliers += 1
                return ('link echo set aside (%d so far): offset %.6f s +- %.6f s disagrees with '
                        'the estimate %.6f s +- %.6f s (%d such in a row make a clock step)' % (
                            self.outliers, echo.offset_s, rtt_s / 2.0, best.offset_s,
                            best.rtt_s / 2.0, STEP_CONFIRM))
            self.clock_steps += 1   # the intervals miss each other, again and again: a step
            self._window.clear()
            self._window.extend(self._doubt)
        else:
            self._window.append(echo)
        self._doubt = []
        self.echoes += 1
        self.rtt_s = rtt_s
        self._last_echo_s = now_s
        return ''

    def _check_echo(self, now_s, seq, sent_s, echoed_s):
        if not all(isinstance(v, (int, float)) and math.isfinite(v)
                   for v in (seq, sent_s, echoed_s)):
            return 'not finite numbers (seq %r, sent %r, echoed %r)' % (seq, sent_s, echoed_s)
        record = self._sent.get(seq)
        if record is None:
            return 'no ping %r was sent in the last %g s' % (seq, LOSS_WINDOW_S)
        if record[1] is not None:
            return 'ping %d was answered already' % seq
        if abs(sent_s - record[0]) > SENT_TOLERANCE_S:
            return 'ping %d was sent at %.6f, the echo says %.6f' % (seq, record[0], sent_s)
        if echoed_s <= 0.0:
            return 'echoed time %r is not a time' % echoed_s
        if now_s < record[0]:
            return 'it arrived %.6f s before ping %d was sent' % (record[0] - now_s, seq)
        return ''

    # ---- what the echoes tell ---------------------------------------------------------------

    def best(self):
        """Return the Echo with the shortest round trip of the window, or None before any."""
        return min(self._window, key=lambda e: e.rtt_s) if self._window else None

    def offset(self):
        """Return (offset s, error bound s) of the operator clock, or None before any echo."""
        best = self.best()
        return None if best is None else (best.offset_s, best.rtt_s / 2.0)

    def silence_s(self, now_s):
        """Return how long no echo came (since the newest echo, else the first ping; 0 before
        any ping)."""
        since = self._last_echo_s if self._last_echo_s is not None else self._first_ping_s
        return 0.0 if since is None else max(now_s - since, 0.0)

    def clock_problem(self, now_s):
        """Return why sample ages cannot be trusted at now_s, or '' when they can."""
        if self._last_echo_s is None:
            return ("waiting for the operator host's echo (%s): the age of puppet samples is "
                    'unknown' % LINK_ECHO)
        if len(self._doubt) > 1:
            return ('%d echoes in a row disagree with the estimate of the operator clock: a clock '
                    'may have stepped, the age of puppet samples is unknown' % len(self._doubt))
        silence_s = self.silence_s(now_s)
        if silence_s > CLOCK_EXPIRY_S:
            return ('no echo from the operator host for %.1f s: its clock is no longer trusted, '
                    'the age of puppet samples is unknown' % silence_s)
        return ''

    def age(self, now_s, stamp_s):
        """Return the age (s, robot clock) at now_s of a sample stamped stamp_s (operator clock),
        counting the offset's error bound: the sample is at most this old.

        Raises:
            Refused: kind 'stamp' (not a positive finite time, or older than PLAUSIBLE_AGE_S),
                'clock' (the offset is not trusted, see clock_problem) or 'future' (younger than
                the error bound allows).
        """
        if not (isinstance(stamp_s, (int, float)) and math.isfinite(stamp_s) and stamp_s > 0.0):
            raise Refused('stamp', 'its stamp %r is not a time' % (stamp_s,))
        problem = self.clock_problem(now_s)
        if problem:
            raise Refused('clock', problem)
        offset_s, error_s = self.offset()
        age_s = now_s - (stamp_s - offset_s)
        if age_s < -(error_s + FUTURE_TOLERANCE_S):
            raise Refused('future', 'stamped %.3f s ahead of the robot clock (offset %.3f s '
                                    '+- %.3f s)' % (-age_s, offset_s, error_s))
        if age_s > PLAUSIBLE_AGE_S:
            raise Refused('stamp', 'its stamp %.3f is %.0f s before the robot clock (offset %.3f '
                                   's): not a time a sample was taken' % (stamp_s, age_s, offset_s))
        return max(age_s + error_s, 0.0)

    def loss(self, now_s):
        """Return the fraction of the pings of the last LOSS_WINDOW_S (those sent at least
        ECHO_TIMEOUT_S ago) not answered within ECHO_TIMEOUT_S, or None when there are none."""
        decided = [(sent_s, arrived_s) for sent_s, arrived_s in self._sent.values()
                   if now_s - ECHO_TIMEOUT_S - LOSS_WINDOW_S < sent_s <= now_s - ECHO_TIMEOUT_S]
        if not decided:
            return None
        lost = sum(1 for sent_s, arrived_s in decided
                   if arrived_s is None or arrived_s - sent_s > ECHO_TIMEOUT_S)
        return lost / len(decided)


def _agree(echo, best):
    """Return whether two echoes' offset intervals overlap (within CLOCK_STEP_TOLERANCE_S)."""
    return abs(echo.offset_s - best.offset_s) <= (
        (echo.rtt_s + best.rtt_s) / 2.0 + CLOCK_STEP_TOLERANCE_S)
