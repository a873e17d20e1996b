"""What the Baxter stand-in's rostests share: a recording subscriber, waiting, publishers."""
import threading
import time

import rospy
from rosgraph_msgs.msg import Log

from waiting import wait_for


class Latest:
    """Keep the last message of a topic, and while recording all of them with receive times."""

    def __init__(self, topic, msg_type, queue_size=1000):
        self.lock = threading.Lock()
        self.msg, self.log = None, None
        rospy.Subscriber(topic, msg_type, self._on_msg, queue_size=queue_size)

    def _on_msg(self, msg):
        with self.lock:
            self.msg = msg
            if self.log is not None:
                self.log.append((time.monotonic(), msg))

    def record(self):
        """Start recording (again, from now)."""
        with self.lock:
            self.log = []

    def recorded(self):
        """Return [(receive time s, message)] since record(), recording on."""
        with self.lock:
            return list(self.log)

    def stop_recording(self):
        """Stop recording; return [(receive time s, message)] since record()."""
        with self.lock:
            log, self.log = self.log, None
        return log


def warnings(log, node='/baxter_sim'):
    """Return the text of the warnings of node among /rosout messages [(time, Log)]."""
    return [m.msg for _, m in log if m.name == node and m.level == Log.WARN]


def warned(rosout, *words):
    """Return True when rosout (a recording Latest of /rosout) holds a warning of the stand-in
    with all of words."""
    return any(all(w in line for w in words) for line in warnings(rosout.recorded()))


def publisher(topic, msg_type, queue_size=100):
    """Return a publisher on topic once the stand-in subscribes to it."""
    pub = rospy.Publisher(topic, msg_type, queue_size=queue_size)
    wait_for(lambda: pub.get_num_connections() > 0, 10.0, 'a subscriber on ' + topic)
    return pub
