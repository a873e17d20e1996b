"""Everything serial_X decides, in one pure core beneath the node.

Sans-I/O: received bytes, active settings, opmodes and setpoints go in; the outputs to publish
(robopuppet.protocol.state_output), the writes (through the injected write callable) and what
the node must do (re-open the port, publish diagnostics or an opmode, when to step again) come
out; the time comes from the injected clock. No rospy, no thread, not thread-safe: serial_X
makes every call under one lock (robopuppet.protocol.core_runner), so all of the state has one
owner.
"""
import collections
import reprlib

from robopuppet import interface
from robopuppet.protocol import (codec, device_commands, feel_watch, link_health, state_output,
                                 state_set)
from robopuppet.protocol.device_settings import DeviceSettings

DIAGNOSTICS_PERIOD_S = 1.0
IMPLAUSIBLE_LOG_S = 10.0  # an implausible frame is logged at most this often
RATE_LOG_S = 30.0  # a state rate that disagrees with comm_rate is logged at most this often
WRITE_LOG_S = 5.0  # a command that cannot be written is logged at most this often

Actions = collections.namedtuple('Actions', 'reopen diagnostics next_s opmode')
Actions.__doc__ = """What step() asks of the node: reopen (the port, the device is silent),
diagnostics (a link_health.Diagnostics to publish, or None), next_s (clock time of the next step
at the latest), opmode (a mode to publish on <ns>/opmode so that the other nodes know, or
None)."""


class SerialCore:
    """The puppet's link as serial_X sees it: state sets, settings, commands and health.

    Args:
        write(data): put bytes on the port as one write; return False if they did not go out
            (a write that fails after it returned True is reported with on_write_failed).
        clock(): monotonic time, s.
        log_info(text), log_warn(text): where the node's log lines go.
        port_name: the serial port, for log lines and diagnostics.
        source: the active_settings topic, for log lines.
        topic_rate_hz: cap of the per-joint topics (state_output.StateOutput).
        silence_timeout_s: no whole set or heartbeat for this long re-opens the port.
        comm_rate_hz: the state-set rate the firmware is expected to send, 0: no check.
        pause_s: the least time between two settings writes, s.
        feel_timeout_s: in feel mode, no joint setpoint for this long, or no feel gains on the
            device this long after the opmode feel, sends limp (feel_watch.FeelWatch).
    Raises:
        ValueError: a rate or timeout out of range.
    """

    def __init__(self, write, clock, log_info, log_warn, port_name, source, topic_rate_hz=100.0,
                 silence_timeout_s=3.0, comm_rate_hz=0.0, pause_s=device_commands.LOAD_PAUSE_S,
                 feel_timeout_s=0.5):
        if not topic_rate_hz > 0.0 or not comm_rate_hz >= 0.0:
            raise ValueError('the topic rate must be positive and comm_rate positive or 0 (no '
                             'check), got %r and %r' % (topic_rate_hz, comm_rate_hz))
        self._write, self._clock = write, clock
        self._log_info, self._log_warn = log_info, log_warn
        self._port, self._comm_rate_hz = port_name, comm_rate_hz
        self._settings = DeviceSettings(write, clock, log_info, log_warn, source, pause_s)
        self.receiver = state_set.Receiver(self._settings.voltage_limits)
        self._output = state_output.StateOutput(1.0 / topic_rate_hz)
        self._silence = link_health.SilenceWatch(silence_timeout_s)
        self._hold = device_commands.HoldGate()
        self._feel = feel_watch.FeelWatch(feel_timeout_s)
        self._announce = None  # an opmode for the next step() to hand the node, or None
        self._profile = ''  # of the newest active settings taken
        self._parked = None  # (revision, joints, profile) of other settings, until feel ends
        self._rate = device_commands.RateMeter()
        self._rate_epoch = None
        self._heartbeat_s = None
        self._next_diagnostics_s = 0.0
        self._frames_before = 0
        self._errors_reported = 0
        self._logged = {}  # what: clock time of its last throttled log line

    @property
    def loaded(self):
        """Return True while the device holds the active settings, loaded since the last
        (re)connect."""
        return self._settings.loaded_since_s is not None

    # Device -> host ------------------------------------------------------------------------
    def on_connect(self):
        """The port was (re)opened: the device may hold other settings now. Ends feel mode
        (limp, announced): the device may have been silent or replugged meanwhile."""
        if self._feel.active:
            self._go_limp('the port %s was re-opened' % self._port)
        self._silence.on_connect(self._clock())
        # A silent device gets its settings when it talks again.
        self._settings.unload(load=not self._silence.silent)

    def on_data(self, data):
        """Take bytes received from the port; return the outputs to publish, in order."""
        now = self._clock()
        receiver, decoder = self.receiver, self.receiver.decoder
        refused = receiver.implausible_frames + decoder.invalid_frames
        events = receiver.feed(data, now)
        if receiver.implausible_frames + decoder.invalid_frames != refused:
            self._throttled('implausible', IMPLAUSIBLE_LOG_S, 'dropped an implausible frame from '
                            '%s (%d so far): %s' % (self._port, refused + 1, receiver.last_problem))
        if not events:
            return []
        # Only whole sets and healthy heartbeats count as the device talking: noise is not life.
        if self._silence.on_frames(now):
            self._log_info('frames from %s again; reloading the settings in case the device '
                           'restarted' % self._port)
            self._settings.unload(load=True)
        outputs = self._output.on_events(events, now, self._settings.loaded_since_s,
                                         self._settings.angle_tag)
        for output in outputs:
            if type(output) is state_output.Heartbeat:
                self._heartbeat_s = now
            elif type(output) is state_output.JointStates:
                self._on_joint_states(output.positions, now)
        return outputs

    def _on_joint_states(self, positions, now):
        """The hold gets the current angles, and the rate check its count since the load."""
        epoch = self._settings.epoch
        self._hold.on_angles(positions, epoch)
        if epoch != self._rate_epoch:
            self._rate.restart(now)
            self._rate_epoch = epoch
        self._rate.add(now)

    # Host -> device ------------------------------------------------------------------------
    def on_stored(self, revision, joints, profile=''):
        """Take config_X's newest active settings (see DeviceSettings.on_stored); profile ''
        (as stored) or interface.FEEL_PROFILE. In feel mode, settings of another profile wait
        until feel ends (_unpark), so that the device never holds a feel setpoint on them."""
        self._parked = (revision, joints, profile)
        self._unpark()
        self._feel_ready()

    def _unpark(self):
        if self._parked is None or (self._feel.active
                                    and self._parked[2] != interface.FEEL_PROFILE):
            return
        (revision, joints, profile), self._parked = self._parked, None
        if self._settings.on_stored(revision, joints):
            if profile != self._profile:
                self._log_info('active settings revision %d: profile %s' % (
                    revision, reprlib.repr(profile) if profile else "'' (as stored)"))
            self._profile = profile

    def step_due(self):
        """Return True if step() has work now (e.g. after on_stored, a device that talks again
        or an opmode to announce), so that the node steps at once rather than at its next
        planned step."""
        return self._announce is not None or self._settings.next_step_s <= self._clock()

    def on_opmode(self, mode):
        """Take an opmode (interface.OPMODES): send limp, or hold for hold and feel.

        The firmware holds the setpoints it has (0 rad after power-on or limp), so a hold
        without seven setpoints since the last limp/connect first sends the current angles as
        the missing ones, in the same write; with no current angles it is refused (logged; a
        refused feel is limp, announced). Feel is the device's hold on the feel profile's gains:
        the hold goes out once the device holds them (setpoints meanwhile kept, sent just before
        it), then the setpoint watchdog runs (step()). Limp, hold or a reconnect end feel, and
        the settings that waited go out after that opmode; a repeat of feel changes nothing.
        """
        if mode not in interface.OPMODES:
            self._log_warn('opmode must be one of %s, got %s; ignored'
                           % ('/'.join(interface.OPMODES), reprlib.repr(mode)))
            return
        if mode == interface.FEEL:
            if not self._feel.active:
                refusal = self._hold.plan_hold(self._settings.epoch).refusal
                if refusal:
                    self._go_limp('feel refused: %s' % refusal)
                    return
                self._feel.start(self._clock())
                self._feel_ready()
            return
        kept = self._feel.stop()
        if mode == interface.LIMP:
            self._send([codec.Opmode(codec.LIMP)], 'opmode limp')
        else:
            self._send_hold(mode, kept)   # what the device would hold had feel not waited
        self._unpark()

    def on_setpoint(self, joint, angle_rad):
        """Send a joint's setpoint (rad), used by the device in hold (and fed to feel mode's
        watchdog; kept while feel waits for its gains)."""
        if self._feel.on_setpoint(self._clock(), joint, angle_rad):
            self._send([codec.JointSetpoint(joint, angle_rad)], 'joint %d setpoint' % joint)

    def _feel_ready(self):
        """Once the device holds the feel profile in full, send the kept setpoints and feel's
        hold."""
        if self._feel.waiting and self._profile == interface.FEEL_PROFILE \
                and self._settings.holds_stored:
            self._send_hold(interface.FEEL, self._feel.gains_loaded())

    def _send_hold(self, mode, setpoints):
        """Send setpoints (codec.JointSetpoint), then the device's hold for `mode`."""
        plan = self._hold.plan_hold(self._settings.epoch, setpoints)
        if plan.refusal:
            if mode == interface.FEEL:
                self._go_limp('feel refused: %s' % plan.refusal)
            else:
                self._log_warn('hold refused: %s; send joint_J/setpoint for every joint first, '
                               'or wait for the joint states' % plan.refusal)
            return
        filled = [m.joint for m in plan.messages[len(setpoints):-1]]
        if filled:
            self._log_info('%s: joints %s had no setpoint since the last limp or connect; '
                           'their current angles go first' % (mode, filled))
        self._send(plan.messages, 'opmode %s (the device\'s hold)' % mode)

    def _go_limp(self, why):
        """End feel mode: send limp, log why, and have step() announce limp on <ns>/opmode."""
        self._feel.stop()
        self._log_warn('%s; going limp (opmode limp sent and published)' % why)
        self._send([codec.Opmode(codec.LIMP)], 'opmode limp')
        self._announce = interface.LIMP
        self._unpark()

    def _send(self, messages, what):
        """Send messages in whole-frame writes of <= 64 bytes; the hold gate notes them."""
        epoch = self._settings.epoch  # before the write: see device_commands.HoldGate
        try:
            writes = device_commands.pack([codec.encode(m) for m in messages])
        except codec.CodecError as error:
            self._log_warn('not sending %s: %s' % (what, error))
            return
        if not all(self._write(data) for data in writes):
            self._throttled('write', WRITE_LOG_S, '%s not sent: serial port %s is not connected'
                            % (what, self._port))
            return
        self._hold.record(messages, epoch)

    def on_write_failed(self):
        """A write that write() took failed at the port: the device may lack what it carried, so
        everything is loaded again (DeviceSettings.write_failed). Writes nothing."""
        self._settings.write_failed()

    # Timing and health -----------------------------------------------------------------------
    def step(self, link):
        """Do what is due: a settings write, a re-open of a silent port, the diagnostics.

        Args:
            link: the link_health.LinkFacts of now.
        Returns:
            Actions for the node.
        """
        self._settings.step()
        self._feel_ready()
        now = self._clock()
        why = self._feel.expired(now)
        if why:
            self._go_limp(why)
        announce, self._announce = self._announce, None
        was_silent = self._silence.silent
        quiet_s = self._silence.check(now, link.connected)
        if quiet_s is not None and not was_silent:
            self._log_warn('no frame from %s for %.1f s; re-opening the port every %.0f s until '
                           'it talks' % (self._port, quiet_s, link_health.WAKE_S))
        diagnostics = None
        if now >= self._next_diagnostics_s:
            diagnostics = self._diagnostics(now, link)
            self._next_diagnostics_s = now + DIAGNOSTICS_PERIOD_S
        next_s = min(self._settings.next_step_s, self._silence.due_s(link.connected),
                     self._next_diagnostics_s, self._feel.due_s)
        return Actions(quiet_s is not None, diagnostics, next_s, announce)

    def _diagnostics(self, now, link):
        rate_hz = self._rate.rate_hz(now)
        rate = device_commands.rate_problem(rate_hz, self._comm_rate_hz)
        if rate:
            self._throttled('rate', RATE_LOG_S, rate)
        new_errors = link.callback_errors - self._errors_reported
        self._errors_reported = link.callback_errors
        age_s = None if self._heartbeat_s is None else now - self._heartbeat_s
        frames = self.receiver.decoder.frames
        frames_per_s, self._frames_before = frames - self._frames_before, frames
        return link_health.diagnostics(link_health.Health(
            link.connected, self._port, self._silence.silent, self.loaded, self._settings.revision,
            link.publishers, age_s, rate, new_errors, link.last_error), link, self.receiver,
            self._profile, frames_per_s, rate_hz, self._comm_rate_hz)

    def _throttled(self, what, period_s, text):
        """Log a warning, but a warning of the same kind at most once per period_s."""
        now = self._clock()
        last = self._logged.get(what)
        if last is None or now - last >= period_s:
            self._logged[what] = now
            self._log_warn(text)
