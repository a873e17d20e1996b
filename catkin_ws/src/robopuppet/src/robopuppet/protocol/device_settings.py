"""The settings side of serial_X: the puppet holds the newest settings config_X stored.

Pure (sans-I/O): stored settings, unloads and steps go in; writes go out through the injected
write callable, the time comes from the injected clock. No rospy, no thread of its own, not
thread-safe: the node calls it under its one lock.

config_X publishes every state of the settings the device should hold (active_settings, latched:
the stored settings, or in feel mode those with its gentle gains; called "stored" here). After each
(re)connect all 84 settings of the newest stored state are written to the device, then opmode
limp; until that is done (and while none has arrived) the node publishes no joint angles. Every
later stored state is sent at once, but only the values that differ from what the device holds.
The frames' order and their grouping into writes are robopuppet.protocol.device_commands' (signs
before home_angle; whole frames, <= 64 bytes per write), one write per step, at least pause_s
apart (the USB packet rule of docs/serial.md).
"""
import math
import reprlib

from robopuppet import settings
from robopuppet.float32 import to_float32
from robopuppet.protocol import codec, device_commands

RETRY_S = 1.0  # after a failed write, load everything again this much later
# What the device may hold when the host does not know (after a (re)connect): any value the
# hardware takes. Used for the plausibility of reported voltages.
VOLTAGE_BOUNDS_V = (settings.BY_NAME['voltage_min'].low, settings.BY_NAME['voltage_max'].high)


class _Batch:
    """The writes that carry some settings (and, for a load, the limp after them)."""

    def __init__(self, writes, values, load, revision):
        self.writes = writes  # bytes per write, in order
        self.values = values  # {joint: [(name, value)]} they carry
        self.load = load  # a full load, ending with opmode limp
        self.revision = revision
        self.sent = 0  # writes done


class DeviceSettings:
    """Keep the device holding the newest stored settings.

    Args:
        write(data): put bytes on the link; return False if they did not all go out.
        clock(): monotonic time in s.
        log_info(text), log_warn(text): where the state changes are reported.
        source: where stored settings come from, for log lines (the topic).
        pause_s: the least time between two writes in s.
    Nothing is written before the first unload() (the first connect).
    Attributes:
        revision: of the newest stored settings (None before any arrived).
        loaded_since_s: when the load after the last unload() finished (clock time, s), or
            None while the device does not hold stored settings in full.
        epoch: raised at every unload() and after a load's limp frame is written: whenever the
            device may have lost its setpoints (see device_commands.HoldGate).
        angle_tag: settings.angle_tag of the newest settings whose writing has begun ('' before
            any): set before a batch's first write, so that every state set read after it (the
            device may report with the new meaning from then on) carries it.
    """

    def __init__(self, write, clock, log_info, log_warn, source,
                 pause_s=device_commands.LOAD_PAUSE_S):
        self._write, self._clock = write, clock
        self._log_info, self._log_warn = log_info, log_warn
        self._source, self._pause_s = source, pause_s
        self._stored = None  # {joint: {name: value}}, the newest stored settings
        self._held = dict.fromkeys(settings.JOINTS)  # joint: {name: value} or None (unknown)
        self._batch = None  # being written
        self._dirty = True  # the stored or the held settings changed since the last batch
        self._hold_off = True  # not connected yet, or a silent device: no load until unload()
        self._next_s = 0.0  # no write before this time
        self._failing = False  # the last batch failed: its retries are not logged again
        self._waiting_logged = False
        self.revision = None
        self.loaded_since_s = None
        self.epoch = 0
        self.angle_tag = ''

    def on_stored(self, revision, joints):
        """Take a new stored state of the settings; return False when it is bad (logged and
        ignored).

        Args:
            revision: config_X's count of stored changes (for log lines and diagnostics).
            joints: (joint, {name: value}) pairs, one per joint 0..6, every name of
                settings.NAMES, values in their units (rad, rad/s, V, gains, signs).
        """
        joints = [(joint, {name: float(values[name]) for name in settings.NAMES})
                  for joint, values in joints]
        problem = _problem(joints)
        if problem:
            self._log_warn('stored settings revision %d from %s ignored: %s'
                           % (revision, self._source, problem))
            return False
        self._stored, self.revision, self._dirty = dict(joints), revision, True
        return True

    def unload(self, load=True):
        """The device may hold anything now (a (re)connect, or it talks again after silence):
        forget what it holds and any batch being written; load everything again, at once if
        `load`, else only after the next unload(load=True)."""
        self._held = dict.fromkeys(settings.JOINTS)
        self._batch = None
        self._dirty = True
        self._hold_off = not load
        self._next_s = 0.0
        self._waiting_logged = False
        self.loaded_since_s = None
        self.epoch += 1

    @property
    def holds_stored(self):
        """True when the device holds the newest stored settings in full (loaded since the last
        unload, none left to write)."""
        return self.loaded_since_s is not None and self._batch is None and all(
            self._held[j] == self._stored[j] for j in settings.JOINTS)

    def held(self, joint):
        """Return a copy of {setting name: value} that the device holds for a joint, as far as
        this node wrote it, or None when that is not known (since the last unload)."""
        held = self._held[joint]
        return None if held is None else dict(held)

    def voltage_limits(self, joint):
        """Return the (min, max) motor voltage in V the device holds for a joint (the hardware's
        bounds while that is not known)."""
        held = self._held[joint]
        return VOLTAGE_BOUNDS_V if held is None else (held['voltage_min'], held['voltage_max'])

    @property
    def next_step_s(self):
        """Return the clock time at which step() has work, math.inf if it has none."""
        if self._hold_off or self._stored is None or (self._batch is None and not self._dirty):
            return math.inf
        return self._next_s

    def step(self):
        """Write the next write due (at most one), or start the batch the device needs."""
        now = self._clock()
        if self._hold_off or now < self._next_s:
            return
        if self._stored is None:
            if not self._waiting_logged:
                self._log_warn('no settings from %s yet; publishing no joint states until '
                               'they arrive and are loaded' % self._source)
                self._waiting_logged = True
            return
        if self._batch is None:
            self._batch = self._make_batch() if self._dirty else None
            self._dirty = False
            if self._batch is None:
                return
            self.angle_tag = settings.angle_tag([self._stored[j] for j in settings.JOINTS])
        batch = self._batch
        written = self._write(batch.writes[batch.sent])
        if self._batch is not batch:
            return  # unload() during the write: what the batch carries is not held
        if not written:
            self._failed('settings (revision %d) not sent: a write failed' % batch.revision)
            return
        batch.sent += 1
        self._next_s = self._clock() + self._pause_s
        if batch.sent == len(batch.writes):
            self._done(batch)

    def write_failed(self):
        """A write that write() took failed later: the device may lack what it carried, so load
        everything again RETRY_S later (or after the next unload)."""
        self._failed('a write to the device failed: the settings it holds are not known')

    def _make_batch(self):
        """Return the batch that makes the device hold the stored settings, or None."""
        values = {}
        for joint in settings.JOINTS:
            changes = device_commands.settings_to_send(self._stored[joint], self._held[joint])
            if changes:
                values[joint] = changes
        load = self.loaded_since_s is None
        if not values and not load:
            return None
        frames = [codec.encode(codec.JointConfig(joint, settings.CONFIG_ID[name], value))
                  for joint, changes in values.items() for name, value in changes]
        if load:
            frames.append(codec.encode(codec.Opmode(codec.LIMP)))
        return _Batch(device_commands.pack(frames), values, load, self.revision)

    def _done(self, batch):
        self._batch = None
        self._failing = False
        for joint, changes in batch.values.items():
            self._held[joint] = dict(self._held[joint] or {}, **dict(changes))
        sent = ['joint %d %s' % (j, name) for j, changes in batch.values.items()
                for name, _ in changes]
        if batch.load:
            self.epoch += 1  # after the limp frame went out: see device_commands.HoldGate
            self.loaded_since_s = self._clock()
            self._log_info('loaded %d settings (revision %d) into the puppet, opmode limp; '
                           'publishing joint states' % (len(sent), batch.revision))
        else:
            self._log_info('settings revision %d: sent %s' % (batch.revision, ', '.join(sent)))

    def _failed(self, why):
        if not self._failing:
            self._log_warn('%s; loading all of them again in %.0f s or after the reconnect'
                           % (why, RETRY_S))
        self.unload(load=True)
        self._failing = True
        self._next_s = self._clock() + RETRY_S


def _problem(joints):
    """Return why (joint, {name: value}) pairs cannot go to the device, or None if they can.

    Besides the wire format, the bounds of settings.SETTINGS (signs +-1) and the ranges'
    rules (settings.range_problems): config_X never publishes other values, but
    anyone may publish on active_settings, and a sign_angle of 4 would make every later frame
    implausible (dropped), a negative gain drive a motor away from its setpoint.
    """
    numbers = sorted(joint for joint, _ in joints)
    if numbers != list(settings.JOINTS):
        return 'joints %s, not one each of %s' % (reprlib.repr(numbers), list(settings.JOINTS))
    for joint, values in joints:
        for name, value in values.items():
            try:
                codec.encode(codec.JointConfig(joint, settings.CONFIG_ID[name], value))
            except codec.CodecError as error:
                return 'joint %d %s: %s' % (joint, name, error)
            why = settings.implausible(name, to_float32(value))   # as the frame carries it
            if why:
                return 'joint %d %s = %r: %s' % (joint, name, value, why)
        for _, _, why in settings.range_problems(values):
            return 'joint %d %s' % (joint, why)
    return None
