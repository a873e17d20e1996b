"""What arm_X makes of the operator-robot link: which puppet samples are fresh enough to use, and
the link's report (robopuppet_msgs/LinkState and its /diagnostics status). Pure: robot-clock
seconds are arguments, the clock itself is robopuppet.arm.link_clock.

A puppet sample (joint_states, stamped by serial_X on the operator clock) is used only when its
age is known (the operator clock is trusted), it is not stamped in the future, it is newer than
every sample used before (out of order: refused), and it is at most the bound old on arrival
(robopuppet.arm.timing.sample_age_bound). "Newer than" compares with a stamp the current
estimate still allows: a used stamp that now lies in the future (a garbage sample let through
under an estimate since refined, or a clock step) is forgotten (counted in `reanchored`), so that
no single sample can make every later one "out of order" for longer than the offset's error
bound. Refusals are counted by kind. One of unknown age
(STALE_KINDS) makes the stream stale at once: teleop takes it as a silent puppet. One too old
(LATE) is dropped: never used, counted and reported (a warning for LOSS_WINDOW_S); the stream is
stale only when no usable sample comes for the state timeout, and teleop then names the newest
late sample's age (robopuppet.arm.timing says why).

The report's fault names the most severe problem, ties going upstream first (network, then
operator, then robot); its detail lists them all; level OK goes with fault none only. All the
thresholds are below, in one place.
"""
import collections

from robopuppet.arm.link_clock import ECHO_TIMEOUT_S, LOSS_WINDOW_S, LinkClock, Refused
from robopuppet.interface import DIAG_NETWORK, puppet_ns

# robopuppet_msgs/LinkState's fault constants, and diagnostic_msgs/DiagnosticStatus's levels.
NONE, OPERATOR, NETWORK, ROBOT = 'none', 'operator', 'network', 'robot'
OK, WARN, ERROR = 0, 1, 2
PRIORITY = (NETWORK, OPERATOR, ROBOT)    # ties: the upstream problem explains the others

# ---- thresholds -------------------------------------------------------------------------------
LOSS_WARN, LOSS_ERROR = 0.05, 0.25  # fraction of the pings of LOSS_WINDOW_S unanswered
RTT_WARN_S = 0.1                    # newest round trip (s); unanswered pings are the error
AGE_WARN_FRACTION = 0.5             # samples arriving older than this part of the bound: WARN
ECHO_SILENCE_ERROR_S = ECHO_TIMEOUT_S   # no echo for this long: pings go unanswered, ERROR
# Refusal kinds and whose problem they are: the network's (late, or ages unknown because pings
# go unanswered) or the operator host's (what it stamps).
REFUSAL_FAULT = {'old': NETWORK, 'clock': NETWORK, 'stamp': OPERATOR, 'future': OPERATOR,
                 'order': OPERATOR}
STALE_KINDS = ('clock',)            # refusals that make the stream stale at once
LATE = 'old'                        # the refusal of a sample older than the bound: dropped
REPORT_PERIOD_S = 0.2               # LinkState goes out at 5 Hz

LinkReport = collections.namedtuple('LinkReport', 'rtt_s clock_offset_s clock_known sample_age_s '
                                                  'max_sample_age_s loss level fault detail '
                                                  'diag_name hardware_id message values')
LinkReport.__doc__ = """The link's report: LinkState's fields (rtt_s and sample_age_s -1 before
the first, loss -1 before any ping was decided, level 0-2), and the DiagnosticStatus's name,
hardware_id, message and values [(key, text)] with the same figures."""


class LinkWatch:
    """Judge puppet samples by their age, and report the link.

    Args:
        side: the puppet's side, 'L' or 'R'.
        bound: the timing.AgeBound (bound_s: the oldest usable sample on arrival).
        silent_after_s: no usable sample for this long is a problem (the state timeout).
    Attributes:
        clock: the LinkClock (pings, echoes, offset, loss).
        refused: {kind: samples refused} (kinds: REFUSAL_FAULT's keys).
        reanchored: times the newest used stamp was forgotten, in the future on the estimate.
        sample_age_s: age on arrival of the newest sample whose age is known (s), or None.
    """

    def __init__(self, side, bound, silent_after_s):
        self.clock = LinkClock()
        self.bound, self.silent_after_s = bound, silent_after_s
        self.refused = collections.Counter()
        self.reanchored = 0
        self.sample_age_s = None
        self.diag_name = 'arm_%s: %s' % (side, DIAG_NETWORK)
        self.hardware_id = puppet_ns(side)
        self._used_stamp_s = None   # operator stamp of the newest used sample
        self._used_s = None         # when (robot clock) the newest used sample arrived
        self._refusal = None        # (kind, why) of the newest refusal since the newest use
        self._late = collections.deque()   # (arrival s, age s) of the late samples dropped
        self._steps_seen = 0
        self._report_s = None

    def take(self, now_s, stamp_s):
        """Return the age (s) of a sample stamped stamp_s (operator clock) arriving at now_s, or
        raise Refused (counted) when it may not be used."""
        if self.clock.clock_steps != self._steps_seen:
            self._steps_seen = self.clock.clock_steps   # stamps before a step do not compare
            self._used_stamp_s = None
        try:
            age_s = self.clock.age(now_s, stamp_s)
            self.sample_age_s = age_s
            self._check_used(now_s)
            if self._used_stamp_s is not None and stamp_s <= self._used_stamp_s:
                raise Refused('order', 'out of order: stamped %.3f s before one already used'
                              % (self._used_stamp_s - stamp_s))
            if age_s > self.bound.bound_s:
                raise Refused('old', '%.3f s old, over the %.2f s bound (max_sample_age)'
                              % (age_s, self.bound.bound_s))
        except Refused as refusal:
            self.refused[refusal.kind] += 1
            if refusal.kind == LATE:
                self.late_dropped(now_s)   # keeps the window's only
                self._late.append((now_s, age_s))
            self._refusal = (refusal.kind, str(refusal))
            raise
        self._used_stamp_s, self._used_s, self._refusal = stamp_s, now_s, None
        return age_s

    def _check_used(self, now_s):
        if self._used_stamp_s is None:
            return
        try:
            self.clock.age(now_s, self._used_stamp_s)
        except Refused as refusal:
            if refusal.kind == 'future':   # the estimate no longer allows it: forget it
                self._used_stamp_s = None
                self.reanchored += 1

    def late_dropped(self, now_s):
        """Return [(arrival s, age s)] of the late samples dropped in the last LOSS_WINDOW_S."""
        while self._late and self._late[0][0] < now_s - LOSS_WINDOW_S:
            self._late.popleft()
        return list(self._late)

    def since_usable_s(self, now_s):
        """Return how long (s) ago the newest used sample arrived, or None before the first."""
        return None if self._used_s is None else now_s - self._used_s

    def problems(self, now_s, robot_ok):
        """Return [(level, fault, text)] of what is wrong with the link at now_s."""
        found, clock = [], self.clock
        silence_s, clock_problem = clock.silence_s(now_s), clock.clock_problem(now_s)
        if silence_s > ECHO_SILENCE_ERROR_S:
            found.append((ERROR, NETWORK, 'pings unanswered: no echo from the operator host for '
                                          '%.1f s%s' % (silence_s, clock_problem and (
                                              ': the age of puppet samples is unknown, Baxter '
                                              'cannot follow'))))
        elif clock_problem:   # waiting for the first echo (a warning until it is late), or
            found.append((ERROR if clock.echoes else WARN, NETWORK,   # an uncertain offset
                          clock_problem + ': Baxter cannot follow'))
        loss = clock.loss(now_s)
        if loss is not None and loss >= LOSS_WARN:
            found.append((ERROR if loss >= LOSS_ERROR else WARN, NETWORK,
                          '%.0f %% of the pings of the last %g s unanswered' % (
                              100.0 * loss, LOSS_WINDOW_S)))
        if clock.rtt_s is not None and clock.rtt_s >= RTT_WARN_S and silence_s <= ECHO_TIMEOUT_S:
            found.append((WARN, NETWORK, 'slow: round trip %.3f s' % clock.rtt_s))
        found += self._sample_problems(now_s, bool(clock_problem))
        if not robot_ok:
            found.append((WARN, ROBOT, 'Baxter is absent or not enabled'))
        return found

    def _sample_problems(self, now_s, clock_untrusted):
        bound_s, since_s, late_s = self.bound.bound_s, self.since_usable_s(now_s), self.sample_age_s
        kind, why = self._refusal or (None, '')
        if kind in STALE_KINDS:
            return []   # unknown ages are the clock's problem, said above
        late = self.late_dropped(now_s)
        if since_s is not None and since_s <= self.silent_after_s:
            if late:
                return [(WARN, NETWORK, '%d puppet sample%s of the last %g s dropped: arrived '
                                        'over the %.2f s bound, the newest %.2f s old' % (
                                            len(late), 's' if len(late) > 1 else '',
                                            LOSS_WINDOW_S, bound_s, late[-1][1]))]
            if late_s is not None and late_s > AGE_WARN_FRACTION * bound_s:
                return [(WARN, NETWORK, 'puppet samples arrive %.2f s old (bound %.2f s)'
                         % (late_s, bound_s))]
            return []
        none = ('no usable puppet sample yet' if since_s is None else
                'no usable puppet sample for %.2f s' % since_s)
        if kind == LATE:
            return [(ERROR, NETWORK, 'puppet samples arrive too late: %s, the newest %s: Baxter '
                                     'does not follow' % (none, why))]
        if kind is not None:
            return [(ERROR, REFUSAL_FAULT[kind], '%s; refused: %s: Baxter does not follow'
                     % (none, why))]
        if clock_untrusted:
            return []   # the clock's own problem says it; nothing arrives besides
        if late_s is not None and late_s > AGE_WARN_FRACTION * bound_s:
            return [(ERROR, NETWORK, '%s; the last one arrived %.2f s old, newer ones are late: '
                                     'Baxter does not follow' % (none, late_s))]
        return [(ERROR, OPERATOR, 'the operator host answers but its puppet sends no joint '
                                  'states (%s): Baxter does not follow' % none)]

    def report(self, now_s, robot_ok):
        """Return the LinkReport when one is due (every REPORT_PERIOD_S), else None."""
        if self._report_s is not None and now_s - self._report_s < REPORT_PERIOD_S:
            return None
        self._report_s = now_s
        found = sorted(self.problems(now_s, robot_ok),
                       key=lambda p: (-p[0], PRIORITY.index(p[1])))
        level, fault = (found[0][0], found[0][1]) if found else (OK, NONE)
        detail = '; '.join(text for _, _, text in found) or 'the link is healthy'
        clock, estimate = self.clock, self.clock.offset()
        offset_s, error_s = estimate if estimate else (0.0, -1.0)
        known = estimate is not None and not clock.clock_problem(now_s)
        loss = clock.loss(now_s)
        rtt_s = -1.0 if clock.rtt_s is None else clock.rtt_s
        age_s = -1.0 if self.sample_age_s is None else self.sample_age_s
        since_s = self.since_usable_s(now_s)
        values = [
            ('fault', fault), ('rtt_s', '%.4f' % rtt_s), ('clock_offset_s', '%.4f' % offset_s),
            ('clock_error_s', '%.4f' % error_s), ('clock_known', known),
            ('sample_age_s', '%.3f' % age_s), ('max_sample_age_s', '%.2f' % self.bound.bound_s),
            ('late_dropped_last_%gs' % LOSS_WINDOW_S, len(self.late_dropped(now_s))),
            ('since_usable_sample_s', '-1' if since_s is None else '%.3f' % since_s),
            ('loss', '-1' if loss is None else '%.3f' % loss),
            ('follows_within_s', '%.2f' % self.bound.late_s),
            ('pings', clock.pings), ('echoes', clock.echoes),
            ('ignored_echoes', clock.ignored_echoes), ('outlier_echoes', clock.outliers),
            ('clock_steps', clock.clock_steps), ('reanchored', self.reanchored)]
        values += [('refused_' + kind, self.refused[kind]) for kind in sorted(REFUSAL_FAULT)]
        return LinkReport(rtt_s, offset_s, known, age_s, self.bound.bound_s,
                          -1.0 if loss is None else loss, level, fault, detail, self.diag_name,
                          self.hardware_id, '%s: %s' % (fault, detail),
                          [(key, str(value)) for key, value in values])
