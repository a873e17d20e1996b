"""Where the simulated participant's actions go: FIFOs, marker feedback, the simulated puppets.

Events (participant_hands.Event) are written as input_events records, each batch ended by
EV_SYN/SYN_REPORT, to every FIFO of the trial's sides (a real device's readers all get every
event); marker poses and menu selects are InteractiveMarkerFeedback on marker_server(X)/feedback,
RViz's own path; the puppet's hand, buttons and end piece go through assist.sim_hands.SimHands,
whose blocking presses and calibrations run on a worker thread.
"""
import errno
import os
import stat
import threading

import rospy
from geometry_msgs.msg import Point, Pose, Quaternion
from visualization_msgs.msg import InteractiveMarkerFeedback

from robopuppet import interface
from robopuppet.assist.sim_hands import FOLLOW_BUTTON, SimHands, SimHandsError
from robopuppet.study import input_events
from robopuppet.study import participant_hands as ph

ARM = {'L': 'left', 'R': 'right'}
CLIENT_ID = '/sim_participant'   # one client id: the marker server takes one client at a time
MARKER_NAME = 'gripper'


def make_fifo(path):
    """Make a FIFO at path unless one is there (OSError: something else is)."""
    os.makedirs(os.path.dirname(path) or '.', exist_ok=True)
    try:
        os.mkfifo(path)
    except FileExistsError:
        if not stat.S_ISFIFO(os.stat(path).st_mode):
            raise


class FifoWriter:
    """Write to FIFOs without blocking; a FIFO nobody reads is skipped (its device not up)."""

    def __init__(self):
        self._fds = {}

    def write(self, path, data):
        """Write data to the FIFO at path; return False when it could not (no reader, full)."""
        fd = self._fds.get(path)
        if fd is None:
            try:
                fd = self._fds[path] = os.open(path, os.O_WRONLY | os.O_NONBLOCK)
            except OSError as error:
                if error.errno not in (errno.ENXIO, errno.ENOENT):
                    rospy.logwarn_throttle(5.0, 'cannot open %s: %s' % (path, error))
                return False
        try:
            os.write(fd, data)
            return True
        except BlockingIOError:
            rospy.logwarn_throttle(5.0, '%s is full: events dropped' % path)
        except OSError:   # the reader went away (EPIPE): open again when one comes
            os.close(self._fds.pop(path))
        return False

    def close(self):
        """Close every FIFO."""
        for fd in self._fds.values():
            os.close(fd)
        self._fds.clear()


class Outputs:
    """The participant's outputs. Args: events {device: FIFO path prefix} (FIFOs made at once,
    <prefix>_L and <prefix>_R). Publishes marker_server(X)/feedback, SimHands' topics."""

    def __init__(self, events):
        self._events = dict(events)
        for prefix in self._events.values():
            for side in interface.PUPPET_SIDES:
                make_fifo('%s_%s' % (prefix, side))
        self._fifos = FifoWriter()
        self._feedback = {side: rospy.Publisher(
            interface.marker_server(side) + '/feedback', InteractiveMarkerFeedback,
            queue_size=20) for side in interface.PUPPET_SIDES}
        self.hands = SimHands(interface.BAXTER_SIDES)
        self._busy = {}   # side -> the worker thread of a blocking press or calibration

    def send(self, t, device, sides, actions):
        """Carry out one step's actions for the trial's device on its puppet sides."""
        events = [a for a in actions if isinstance(a, ph.Event)]
        if events:
            data = b''.join(input_events.encode(input_events.InputEvent(t, *a)) for a in events)
            data += input_events.encode(input_events.sync(t))
            for side in sides:
                self._fifos.write('%s_%s' % (self._events.get(device, ''), side), data)
        for action in actions:
            if isinstance(action, (ph.MarkerPose, ph.MarkerMenu)):
                self._marker(action)
            elif isinstance(action, ph.Hand):
                self.hands.pose(ARM[action.side], action.angles)
            elif isinstance(action, ph.EndPiece):
                self.hands.grip(ARM[action.side], action.closed)
            elif isinstance(action, ph.Press):
                arm = ARM[action.side]
                self._work(action.side, lambda: self.hands.press(arm, FOLLOW_BUTTON[arm]))
            elif isinstance(action, ph.Calibrate):
                arm, angles = ARM[action.side], action.angles
                self._work(action.side, lambda: self.hands.calibrate(arm, angles))

    def _marker(self, action):
        msg = InteractiveMarkerFeedback(client_id=CLIENT_ID, marker_name=MARKER_NAME)
        msg.header.stamp, msg.header.frame_id = rospy.Time.now(), 'base'
        if isinstance(action, ph.MarkerPose):
            msg.event_type = InteractiveMarkerFeedback.POSE_UPDATE
            msg.pose = Pose(Point(*action.xyz), Quaternion(*action.quat))
        else:
            msg.event_type = InteractiveMarkerFeedback.MENU_SELECT
            msg.menu_entry_id = action.entry
            msg.pose.orientation.w = 1.0
        self._feedback[action.side].publish(msg)

    def _work(self, side, job):
        """Run a blocking SimHands job for a side unless one runs; failures are logged."""
        if self._busy.get(side) is not None and self._busy[side].is_alive():
            return

        def run():
            try:
                job()
            except SimHandsError as error:
                rospy.logwarn('sim_participant: %s' % error)
        self._busy[side] = threading.Thread(target=run, daemon=True)
        self._busy[side].start()

    def close(self):
        """Close the FIFOs."""
        self._fifos.close()
