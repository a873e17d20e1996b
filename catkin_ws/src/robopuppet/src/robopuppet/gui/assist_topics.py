"""The GUI's subscription to the assist node's state (robopuppet.assist), kept for the Assist box.

No Qt here: the callback runs on rospy's thread and only sets the locked latest state; the GUI
thread reads it once per frame (gui.assist_box). The Stop/Start commands go out through
gui.command_topics.
"""
import collections
import threading

import rospy

from robopuppet import interface
from robopuppet_msgs.msg import AssistState

# The assist node's state (robopuppet_msgs/AssistState's fields; confidence 0..1) with the GUI's
# own receive time (s).
Assist = collections.namedtuple('Assist', 'state leader follower task method confidence detail '
                                          'received_s')


class AssistTopics:
    """Keep the assist node's latest state.

    Subscribes interface.ASSIST_STATE (robopuppet_msgs/AssistState, latched; queue 1).

    Args:
        clock: returns the time (s) a message is received at.
    """

    def __init__(self, clock):
        self._assist_clock = clock
        self._assist_lock = threading.Lock()
        self._assist = None
        self._assist_subscriber = rospy.Subscriber(interface.ASSIST_STATE, AssistState,
                                                   self._on_assist, queue_size=1)

    def assist_state(self):
        """Return the assist node's latest Assist, or None before the first."""
        with self._assist_lock:
            return self._assist

    def _on_assist(self, msg):
        assist = Assist(msg.state, msg.leader, msg.follower, msg.task, msg.method,
                        msg.confidence, msg.detail, self._assist_clock())
        with self._assist_lock:
            self._assist = assist
