"""The settings side of serial_X: the puppet holds exactly what config_X stored.

After each (re)connect all 84 settings are read from get_config and written to the device,
then opmode limp; until that is done the node must not publish joint angles (see
robopuppet.protocol.serial_node). A joint_J/<setting> message only marks joint J: its value is never
sent. A re-read of a marked joint from get_config follows shortly after, and every value that
differs from what the device holds is sent, so a value that config_X refused, or could not
write to its file, never reaches the device. The order of the frames and their grouping into
writes are robopuppet.protocol.device_commands' (signs before home_angle; whole frames, <= 64 bytes per
write, a short pause between writes).

get_config is never called on the caller's thread: each call runs on a thread of its own and is
waited for at most CALL_TIMEOUT_S, so a hung config node (e.g. SIGSTOP) delays nothing but the
settings; it is reported as unreachable, and the load is retried until it answers.
"""
import threading
import time

import rospy

from robopuppet import settings
from robopuppet.config import config_store
from robopuppet.protocol import codec, device_commands
from robopuppet_msgs.srv import GetConfig

RETRY_S = 1.0  # pause between attempts to load the settings or to re-read a joint
# A marked joint is re-read this long after its last mark (a burst gives one read), and again
# later in case config_X had not stored the value yet at the first read.
RESYNC_AFTER_S = (0.2, 2.0)
CALL_TIMEOUT_S = 2.0  # the longest wait for get_config (incl. up to 1 s for the service)
MAX_STUCK_CALLS = 3  # calls left hanging in a hung config node; no more are started
PROBE_S = 5.0  # with nothing else to ask, ask get_config this often whether it answers

# config_status values
UNKNOWN, REACHABLE, ABSENT, UNREACHABLE = 'unknown', 'reachable', 'not available', 'unreachable'


class CallTimeout(Exception):
    """A call did not return in time, or too many earlier calls still hang."""


class TimedCaller:
    """Run blocking calls on threads of their own, waiting at most timeout_s for each.

    A call that does not return in time is left running (a hung peer answers or dies some
    time) and counted in `stuck` until it returns; while max_stuck calls hang, no new call is
    started. Thread-safe.
    """

    def __init__(self, timeout_s, max_stuck):
        self._timeout_s, self._max_stuck = timeout_s, max_stuck
        self._lock = threading.Lock()
        self.stuck = 0

    def call(self, function, *args):
        """Return function(*args) or raise what it raised.

        Raises:
            CallTimeout: no return within timeout_s, or max_stuck calls hang already.
        """
        with self._lock:
            if self.stuck >= self._max_stuck:
                raise CallTimeout('%d earlier calls still hang' % self.stuck)
        box, finished = {'done': False, 'late': False}, threading.Event()

        def run():
            try:
                box['result'] = function(*args)
            except Exception as error:  # pylint: disable=broad-except  # re-raised below
                box['error'] = error
            finally:
                with self._lock:
                    box['done'] = True
                    if box['late']:
                        self.stuck -= 1
                finished.set()

        threading.Thread(target=run, name='get_config call', daemon=True).start()
        finished.wait(self._timeout_s)
        with self._lock:
            if not box['done']:
                box['late'] = True
                self.stuck += 1
                raise CallTimeout('no answer within %.1f s' % self._timeout_s)
        if 'error' in box:
            raise box['error']
        return box['result']


class DeviceSettings:
    """Load the settings into the device after each (re)connect; re-sync marked joints.

    Args:
        ns: the arm's namespace, /puppet/arm_X, where get_config is.
        write(data): put bytes on the serial link; return False if that failed.
        name: the node's name, for log lines.
        port_name: the serial port, for log lines.
    Attributes (read from any thread):
        loaded: the settings are in the device since the last unload().
        epoch: raised at every unload() and after the load's limp frame is written: whenever
            the device may have lost its setpoints (see device_commands.HoldGate).
        config_status: UNKNOWN, REACHABLE, ABSENT (not advertised, e.g. not running) or UNREACHABLE
            (it did not answer in time), from the newest call; config_problem says more.
    Threads: unload() from the serial reader thread, mark() from subscriber threads, step()
    from one loop thread of the node's (it waits up to CALL_TIMEOUT_S for get_config).
    """

    def __init__(self, ns, write, name, port_name, pause_s=device_commands.LOAD_PAUSE_S):
        self._ns, self._write, self._name, self._port_name = ns, write, name, port_name
        self._pause_s = pause_s
        self._get_config = rospy.ServiceProxy(ns + '/get_config', GetConfig)
        self._caller = TimedCaller(CALL_TIMEOUT_S, MAX_STUCK_CALLS)
        self._lock = threading.Lock()  # all below but _device
        self._device = config_store.defaults()  # what the device holds; step() only
        self._resync = {}  # joint: times at which to re-read it
        self._generation = 0  # counts unload() calls: a load is good only within one
        self._need_load = False
        self._next_load_s = 0.0
        self._next_probe_s = 0.0
        self._waiting_logged = False
        self.loaded = False
        self.epoch = 0
        self.config_status, self.config_problem = UNKNOWN, ''

    @property
    def stuck_calls(self):
        """Return how many get_config calls hang in the config node now."""
        return self._caller.stuck

    def unload(self, load):
        """The device may hold other settings now (a (re)connect, or it talks again after
        silence): not loaded until the next load, which starts at once if `load`."""
        with self._lock:
            self._generation += 1
            self.epoch += 1
            self.loaded = False
            self._need_load = load
            self._next_load_s = 0.0
            self._waiting_logged = False

    def held(self, joint):
        """Return a copy of {setting name: value} that the device holds for a joint, as far as
        this node sent it (firmware defaults before the first load)."""
        return dict(self._device[joint])

    def mark(self, joint):
        """A joint_J/<setting> message arrived: re-read joint J from get_config soon."""
        now = time.monotonic()
        with self._lock:
            self._resync[joint] = [now + delay for delay in RESYNC_AFTER_S]

    def step(self, connected):
        """Do what is due: load the settings (if connected), re-sync marked joints, or ask
        get_config whether it still answers. Blocks at most about CALL_TIMEOUT_S."""
        with self._lock:
            load = self._need_load and time.monotonic() >= self._next_load_s
        if load and connected:
            self._load()
        elif self.loaded:
            if not self._resync_due() and time.monotonic() >= self._next_probe_s:
                self._call(lambda: self._get_config(0))

    def _call(self, fetch):
        """Return fetch() run with a timeout, or None if get_config failed (status updated)."""
        def attempt():
            self._get_config.wait_for_service(1.0)
            return fetch()
        self._next_probe_s = time.monotonic() + PROBE_S
        try:
            result = self._caller.call(attempt)
        except CallTimeout as error:
            status, problem = UNREACHABLE, 'get_config: %s' % error
        except rospy.ROSException as error:  # wait_for_service timed out
            status, problem = ABSENT, ('get_config not advertised or not taking connections '
                                       '(%s)' % error)
        except rospy.ServiceException as error:
            status, problem = UNREACHABLE, 'get_config failed: %s' % error
        else:
            if self.config_status in (ABSENT, UNREACHABLE):
                rospy.loginfo('%s: config node answers again', self._name)
            self.config_status, self.config_problem = REACHABLE, ''
            return result
        if status != self.config_status:
            rospy.logwarn('%s: config node %s: %s', self._name, status, problem)
        self.config_status, self.config_problem = status, problem
        return None

    def _load(self):
        """Send all settings from get_config, then opmode limp; on failure retry in ~1 s."""
        generation = self._generation
        config = self._call(lambda: {j: self._get_config(j) for j in settings.JOINTS})
        if config is None:
            if not self._waiting_logged:
                rospy.logwarn('%s: cannot load settings from %s/get_config (%s); publishing no '
                              'joint states until they are loaded; retrying every %.0f s',
                              self._name, self._ns, self.config_problem, RETRY_S)
                self._waiting_logged = True
            self._next_load_s = time.monotonic() + RETRY_S
            return
        values = {j: {n: getattr(config[j], n) for n in settings.NAMES} for j in settings.JOINTS}
        sent = self._send([(j, n, v) for j in settings.JOINTS
                           for n, v in device_commands.settings_to_send(values[j])],
                          generation, limp=True)
        if not sent:
            return  # the link failed: it reconnects, and unload() asks for a load again
        with self._lock:
            if generation != self._generation:
                return  # a reconnect meanwhile: load again
            self.loaded = True
            self._need_load = False
        rospy.loginfo('%s: loaded %d settings into the puppet on %s, opmode limp; publishing '
                      'joint states', self._name, len(settings.NAMES) * settings.NUM_JOINTS,
                      self._port_name)

    def _resync_due(self):
        """Re-read each joint whose re-read is due and send the device what differs; return
        whether any was due."""
        now = time.monotonic()
        with self._lock:
            due = [j for j, times in self._resync.items() if times[0] <= now]
        for joint in due:
            values = self._call(lambda j=joint: self._get_config(j))
            if values is None:
                with self._lock:
                    self._resync[joint][0] = time.monotonic() + RETRY_S
                continue
            stored = {n: getattr(values, n) for n in settings.NAMES}
            changes = device_commands.settings_to_send(stored, self._device[joint])
            if self._send([(joint, n, v) for n, v in changes], self._generation):
                with self._lock:
                    times = self._resync[joint]
                    if times[0] <= now:  # else marked again meanwhile: read again later
                        times.pop(0)
                        if not times:
                            del self._resync[joint]
        return bool(due)

    def _send(self, settings_, generation, limp=False):
        """Send [(joint, name, value)] in order (then opmode limp if `limp`) in whole-frame
        writes of <= 64 bytes, pausing between writes; return False if the link failed.

        A value that cannot be encoded (not finite) is logged and skipped. What the device
        holds is updated only if no unload() happened since `generation`.
        """
        frames, good = [], []
        for joint, name, value in settings_:
            try:
                frames.append(codec.encode(codec.JointConfig(joint, settings.CONFIG_ID[name],
                                                             value)))
                good.append((joint, name, value))
            except codec.CodecError as error:
                rospy.logerr('%s: get_config gave joint %d %s = %r (%s); not sent',
                             self._name, joint, name, value, error)
        if limp:
            frames.append(codec.encode(codec.Opmode(codec.LIMP)))
        for index, data in enumerate(device_commands.pack(frames)):
            if index:
                time.sleep(self._pause_s)
            if not self._write(data):
                return False
        with self._lock:
            if limp:
                self.epoch += 1  # after the write: see device_commands.HoldGate
            if generation == self._generation:
                for joint, name, value in good:
                    self._device[joint][name] = value
        return True
