"""How serial_X judges its link: a silence watch and the /diagnostics status.

Pure: no rospy, no clock (time is an argument, in s).
"""
import collections
import math

from robopuppet import interface

# diagnostic_msgs/DiagnosticStatus levels
OK, WARN, ERROR = 0, 1, 2
WAKE_S = 1.0  # while the device is silent, re-open its port this often

Health = collections.namedtuple(
    'Health', 'connected port silent loaded revision publishers heartbeat_age_s rate_problem '
              'new_errors last_error')
Health.__doc__ = """What the diagnostics level and message are made of.

connected (the port is open), port (its name), silent (SilenceWatch.silent), loaded (the device
holds the active settings since the last (re)connect), revision (of the newest active settings,
None before any), publishers (of active_settings, as the subscription sees them),
heartbeat_age_s (None: none yet), rate_problem (device_commands.rate_problem's text or None),
new_errors (callback errors survived since the last status), last_error (the newest one's text).
"""

LinkFacts = collections.namedtuple(
    'LinkFacts', 'connected connects write_errors callback_errors last_error publishers')
LinkFacts.__doc__ = """What the node knows of its port and subscription when it steps the core:
connected (the port is open), connects, write_errors, callback_errors (totals), last_error (the
newest callback error's text), publishers (of active_settings)."""
Diagnostics = collections.namedtuple('Diagnostics', 'level message values')
Diagnostics.__doc__ = """One /diagnostics status: level (OK, WARN or ERROR), message, values
((key, text) pairs)."""


class SilenceWatch:
    """Tell when the device went silent: no whole set and no heartbeat for timeout_s.

    Then the port is to be re-opened, and again every wake_s until frames arrive.
    """

    def __init__(self, timeout_s, wake_s=WAKE_S):
        if not timeout_s > 0.0:
            raise ValueError('the silence timeout must be positive, got %r' % (timeout_s,))
        self._timeout_s, self._wake_s = timeout_s, wake_s
        self._last_s = None  # the newest frame, connect or re-open
        self.silent = False

    def on_connect(self, now_s):
        """The port was (re)opened at now_s: count the silence from here."""
        self._last_s = now_s

    def on_frames(self, now_s):
        """A whole set or a heartbeat arrived at now_s; return True if the device was silent."""
        self._last_s = now_s
        was_silent, self.silent = self.silent, False
        return was_silent

    def due_s(self, connected):
        """Return when check() has something to decide (math.inf: never, e.g. port closed)."""
        if not connected or self._last_s is None:
            return math.inf
        return self._last_s + (self._wake_s if self.silent else self._timeout_s)

    def check(self, now_s, connected):
        """Return the seconds without a frame if the port is to be re-opened now, else None."""
        if now_s < self.due_s(connected):
            return None
        quiet_s = now_s - self._last_s
        self.silent = True
        self._last_s = now_s
        return quiet_s


def level_and_message(health):
    """Return the /diagnostics (level, message) for a Health: the worst problem first."""
    topic = interface.ACTIVE_SETTINGS
    if not health.connected:
        return ERROR, 'link down: %s not open' % health.port
    if health.silent:
        return ERROR, 'device silent'
    if not health.loaded:
        if health.revision is None:
            return WARN, ('waiting for settings: none received on %s yet (%d publishers); '
                          'joint states withheld' % (topic, health.publishers))
        return WARN, 'loading settings (revision %d); joint states withheld' % health.revision
    if health.heartbeat_age_s is None or health.heartbeat_age_s > interface.HEARTBEAT_TIMEOUT_S:
        return WARN, 'link up, no heartbeat'
    if not health.publishers:
        return WARN, ('link up; nothing publishes %s: setting changes do not reach the puppet'
                      % topic)
    if health.rate_problem:
        return WARN, 'link up; ' + health.rate_problem
    if health.new_errors:
        return WARN, ('link up; %d callback errors survived in the last second: %s'
                      % (health.new_errors, health.last_error))
    return OK, 'link up'


def diagnostics(health, link, receiver, profile, frames_per_s, rate_hz, comm_rate_hz):
    """Return the Diagnostics of a Health, its values the link's (LinkFacts) and the receiver's
    (state_set.Receiver) counters, the active settings' profile and the state-set rates (Hz;
    rate_hz None while measuring, comm_rate_hz 0 when unset)."""
    level, message = level_and_message(health)
    rx, dec, revision = receiver, receiver.decoder, health.revision
    values = (
        ('port', health.port), ('link', 'up' if link.connected else 'down'),
        ('settings loaded', str(health.loaded)),
        ('active settings', 'none yet' if revision is None else 'revision %d%s' % (
            revision, ', profile ' + profile if profile else '')),
        ('active settings publishers', str(link.publishers)),
        ('frames per s', str(frames_per_s)),
        ('s since heartbeat', 'never' if health.heartbeat_age_s is None
         else '%.1f' % health.heartbeat_age_s),
        ('dropped bytes', str(dec.dropped_bytes)), ('bad checksums', str(dec.bad_checksums)),
        ('unknown ids', str(dec.unknown_ids)), ('invalid frames', str(dec.invalid_frames)),
        ('incomplete joint sets', str(rx.dropped_sets)), ('stray frames', str(rx.stray_frames)),
        ('implausible frames', str(rx.implausible_frames)),
        ('refused heartbeats', str(rx.refused_heartbeats)),
        ('connects', str(link.connects)), ('write errors', str(link.write_errors)),
        ('state sets per s', 'measuring' if rate_hz is None else '%.1f' % rate_hz),
        ('comm_rate', '%.1f' % comm_rate_hz if comm_rate_hz else 'unset'),
        ('callback errors', str(link.callback_errors)))
    return Diagnostics(level, message, values)
