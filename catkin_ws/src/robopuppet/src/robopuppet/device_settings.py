"""The settings side of serial_X: the puppet holds exactly what config_X stored.

After each (re)connect all 84 settings are read from get_config and written to the device,
then opmode limp; until that is done the node must not publish joint angles (see
robopuppet.serial_node). A joint_J/<setting> message only marks joint J: its value is never
sent. The node's loop re-reads a marked joint from get_config shortly after and sends every
value that differs from what the device holds, so a value that config_X refused, or could not
write to its file, never reaches the device.
"""
import threading
import time

import rospy

from robopuppet import codec, config_store, settings
from robopuppet_msgs.srv import GetConfig

RETRY_S = 1.0  # pause between attempts to load the settings or to re-read a joint
# A marked joint is re-read this long after its last mark (a burst gives one read), and again
# later in case config_X had not stored the value yet at the first read.
RESYNC_AFTER_S = (0.2, 2.0)


class DeviceSettings:
    """Load the settings into the device after each (re)connect; re-sync marked joints.

    Args:
        ns: the arm's namespace, /puppet/arm_X, where get_config is.
        write(data): put bytes on the serial link; return False if that failed.
        name: the node's name, for log lines.
        port_name: the serial port, for log lines.
    Threads: unload() from the serial reader thread, mark() from subscriber threads, step()
    from the node's own loop (it calls get_config, which may block for a second).
    """

    def __init__(self, ns, write, name, port_name):
        self._ns, self._write, self._name, self._port_name = ns, write, name, port_name
        self._get_config = rospy.ServiceProxy(ns + '/get_config', GetConfig)
        self._lock = threading.Lock()  # all below but _device
        self._device = config_store.defaults()  # what the device holds; step() only
        self._resync = {}  # joint: times at which to re-read it
        self._generation = 0  # counts unload() calls: a load is good only within one
        self._need_load = False
        self._next_load_s = 0.0
        self._waiting_logged = False
        self.loaded = False  # the settings are in the device since the last unload()

    def unload(self, load):
        """The device may hold other settings now (a (re)connect, or it talks again after
        silence): not loaded until the next load, which starts at once if `load`."""
        with self._lock:
            self._generation += 1
            self.loaded = False
            self._need_load = load
            self._waiting_logged = False

    def mark(self, joint):
        """A joint_J/<setting> message arrived: re-read joint J from get_config soon."""
        now = time.monotonic()
        with self._lock:
            self._resync[joint] = [now + delay for delay in RESYNC_AFTER_S]

    def step(self, connected):
        """Do what is due: load the settings (if connected), or re-sync marked joints."""
        with self._lock:
            load = self._need_load and time.monotonic() >= self._next_load_s
        if load and connected:
            self._load()
        elif self.loaded:
            self._resync_due()

    def _load(self):
        """Send all settings from get_config, then opmode limp; on failure retry in ~1 s."""
        generation = self._generation
        try:
            self._get_config.wait_for_service(1.0)
            config = {j: self._get_config(j) for j in settings.JOINTS}
        except (rospy.ROSException, rospy.ServiceException) as error:
            if not self._waiting_logged:
                rospy.logwarn('%s: cannot load settings from %s/get_config (%s); publishing no '
                              'joint states until they are loaded; retrying every %.0f s',
                              self._name, self._ns, error, RETRY_S)
                self._waiting_logged = True
            self._next_load_s = time.monotonic() + RETRY_S
            return
        sent = all([self._send(j, {n: getattr(config[j], n) for n in settings.NAMES},
                               generation) for j in settings.JOINTS])
        if not (sent and self._write(codec.encode(codec.Opmode(codec.LIMP)))):
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
        """Re-read each joint whose re-read is due and send the device what differs."""
        now = time.monotonic()
        with self._lock:
            due = [j for j, times in self._resync.items() if times[0] <= now]
        for joint in due:
            try:
                self._get_config.wait_for_service(1.0)
                values = self._get_config(joint)
            except (rospy.ROSException, rospy.ServiceException) as error:
                rospy.logwarn_throttle(10.0, '%s: cannot re-read joint %d from %s/get_config '
                                       '(%s); retrying' % (self._name, joint, self._ns, error))
                with self._lock:
                    self._resync[joint][0] = time.monotonic() + RETRY_S
                continue
            changed = {n: getattr(values, n) for n in settings.NAMES
                       if getattr(values, n) != self._device[joint][n]}
            if self._send(joint, changed, self._generation):
                with self._lock:
                    times = self._resync[joint]
                    if times[0] <= now:  # else marked again meanwhile: read again later
                        times.pop(0)
                        if not times:
                            del self._resync[joint]

    def _send(self, joint, values, generation):
        """Send {name: value} of a joint as one write; return False if the link failed.

        A value that cannot be encoded (not finite) is logged and skipped. What the device
        holds is updated only if no unload() happened since `generation`.
        """
        frames, good = [], {}
        for name, value in values.items():
            try:
                frames.append(codec.encode(codec.JointConfig(joint, settings.CONFIG_ID[name],
                                                             value)))
                good[name] = value
            except codec.CodecError as error:
                rospy.logerr('%s: get_config gave joint %d %s = %r (%s); not sent',
                             self._name, joint, name, value, error)
        if frames and not self._write(b''.join(frames)):
            return False
        if generation == self._generation:
            self._device[joint].update(good)
        return True
