"""input_device: a study device (keyboard, gamepad, SpaceMouse, RViz marker) in serial_X's place."""
import select
import threading
import time

import rospy
from sensor_msgs.msg import JointState

from robopuppet import baxter_description, interface, params, settings
from robopuppet.protocol import state_output as out
from robopuppet.protocol.serial_topics import SerialTopics
from robopuppet.study import input_events, key_jog, pad_axes
from robopuppet.study.cartesian import CartesianArm
from robopuppet.study.device_core import DeviceCore
from robopuppet.study.marker_device import MarkerDevice
from robopuppet_msgs.msg import ArmSettings, TeleopState

DEVICES = ('keyboard', 'gamepad', 'spacemouse', 'marker')   # interface.STUDY_DEVICES but puppet
SLOW_PERIOD_S = 0.1   # enc_stat, buttons and grippers repeat at least this often; heartbeat 1 s


def make_controls(device, side, source):
    """Return the controls of a device read from source (None: the marker's own)."""
    speed = lambda name, default: params.positive('~' + name, rospy.get_param('~' + name,
                                                                               default))
    if device == 'keyboard':
        return key_jog.KeyJog(side, speed('jog_speed', key_jog.DEFAULT_JOG_SPEED))
    if device == 'gamepad':
        return pad_axes.Gamepad(side, speed('max_speed', pad_axes.DEFAULT_MAX_SPEED),
                                source.ranges())
    if device == 'spacemouse':
        return pad_axes.SpaceMouse(side, speed('max_speed', pad_axes.DEFAULT_MAX_SPEED),
                                   speed('max_turn', pad_axes.DEFAULT_MAX_TURN))
    return None


class DeviceNode:
    """Publish what serial_X publishes for one side, made from a study device (device_core).

    Publishes (in <ns> = interface.puppet_ns(~arm_side), through protocol.serial_topics):
        joint_states at ~rate (the 7 angles of Baxter's arm interface.BAXTER_SIDE[side] that the
        device wants, frame_id the angle_tag of <ns>/stored_settings; none before that and
        Baxter's pose are known), heartbeat (1 Hz), joint_J/enc_stat (Working), user_btn (the
        side's follow button while pressed), gripper_G (the end piece: 0 closed, 1 open); echoes
        link_ping on link_echo. The marker also serves interface.marker_server(side).
    Subscribes: <ns>/stored_settings, <ns>/teleop_state (and the other side's: a shared follow
    control), /robot/joint_states.
    Parameters: ~arm_side (L|R), ~device (keyboard|gamepad|spacemouse|marker), ~events (path of
        the event source: /dev/input/..., spacenavd's socket, a FIFO, a file; not for marker;
        a source that fails ends the node, so arm_X stops Baxter), ~rate (Hz, 50),
        ~jog_speed (rad/s, 0.4), ~max_speed (m/s, 0.15), ~max_turn (rad/s, 0.6).
    """

    def __init__(self):
        side = interface.check_side(rospy.get_param('~arm_side'))
        device = rospy.get_param('~device')
        if device not in DEVICES:
            raise ValueError('~device must be one of %s, got %r' % (', '.join(DEVICES), device))
        self._period_s = 1.0 / params.positive('~rate', rospy.get_param('~rate', 50.0))
        baxter_side, ns = interface.BAXTER_SIDE[side], interface.puppet_ns(side) + '/'
        other = 'L' if side == 'R' else 'R'
        other_side, other_ns = interface.BAXTER_SIDE[other], interface.puppet_ns(other) + '/'
        self._names = baxter_description.arm_joint_names(baxter_side)
        arm = CartesianArm(baxter_side)
        events = rospy.get_param('~events', '')
        if device != 'marker' and not events:
            raise ValueError('~events must name the event source of the %s' % device)
        self._source = None if device == 'marker' else input_events.open_source(events)
        self._core = DeviceCore(side, make_controls(device, side, self._source), arm)
        self._lock, self._tag, self._last = threading.Lock(), None, {}
        self._topics = SerialTopics(side, rospy.get_name())
        self._subs = [
            rospy.Subscriber(ns + interface.STORED_SETTINGS, ArmSettings, self._on_stored),
            rospy.Subscriber(ns + interface.TELEOP_STATE, TeleopState, lambda m: self._locked(
                self._core.on_teleop, getattr(m, 'follow_' + baxter_side))),
            rospy.Subscriber(other_ns + interface.TELEOP_STATE, TeleopState, lambda m: self._locked(
                self._core.on_other_teleop, getattr(m, 'follow_' + other_side))),
            rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self._on_robot,
                             queue_size=1, tcp_nodelay=True)]
        self._marker = None
        if device == 'marker':
            self._marker = MarkerDevice(side, self._core, arm, self._lock)

    def _locked(self, method, *args):
        with self._lock:
            return method(*args)

    def _on_stored(self, msg):
        joints = sorted(msg.joints, key=lambda j: j.joint)
        tag = settings.angle_tag([{n: getattr(j, n) for n in settings.ANGLE_SETTINGS}
                                  for j in joints])
        with self._lock:
            self._tag = tag

    def _on_robot(self, msg):
        index = {name: i for i, name in enumerate(msg.name)}
        if all(name in index for name in self._names) and len(msg.position) == len(msg.name):
            self._locked(self._core.on_robot, [msg.position[index[n]] for n in self._names])

    def run(self):
        """Read the device and publish each step until shutdown."""
        next_s = next_slow_s = next_beat_s = time.monotonic()
        while not rospy.is_shutdown():
            wait_s = max(0.0, next_s - time.monotonic())
            if self._source is not None:
                if select.select([self._source], [], [], wait_s)[0]:
                    self._locked(self._core.on_events, self._source.read())
            else:
                rospy.rostime.wallsleep(wait_s)
            now = time.monotonic()
            if now < next_s:
                continue
            next_s = max(next_s + self._period_s, now - self._period_s)
            with self._lock:
                output, tag = self._core.step(now), self._tag
            outputs = []
            if now >= next_beat_s:
                next_beat_s = now + 1.0
                outputs.append(out.Heartbeat())
            if now >= next_slow_s:
                next_slow_s, self._last = now + SLOW_PERIOD_S, {}
                outputs += [out.EncStatus(j, interface.WORKING) for j in settings.JOINTS]
            if output.positions is not None and tag is not None:
                outputs.append(out.JointStates(output.positions, (0.0,) * 7, tag))
            for kind, value in ((out.Button, output.button), (out.Grippers, output.grippers)):
                if self._last.get(kind) != value:
                    self._last[kind] = value
                    outputs.append(kind(value))
            self._topics.publish(outputs)
            if self._marker is not None:
                self._marker.step(now)
        if self._source is not None:
            self._source.close()


def main():
    """Run the input device node until shutdown."""
    rospy.init_node('input_device')
    try:
        node = DeviceNode()
    except (KeyError, ValueError, OSError) as error:
        rospy.logfatal('input device cannot start: %s', error)
        raise SystemExit(1)
    node.run()
