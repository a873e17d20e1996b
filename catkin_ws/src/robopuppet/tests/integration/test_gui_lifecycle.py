#!/usr/bin/python3
"""gui_node.run ends ROS when the window closes, and closes the window when ROS shuts down.

Argument: 'close' (the operator closes the window) or 'shutdown' (rospy shuts down, e.g.
roslaunch stopping or `rosnode kill`, from another thread).
"""
import sys
import threading
import time
import unittest

import rospy
import rostest
from PyQt5 import QtCore

from gui_testing import application, wait_until
from robopuppet.gui import gui_node
from robopuppet.gui.puppet_client import PuppetClient
from robopuppet.gui.state import ArmState
from robopuppet.gui.window import Window

MODE = [arg for arg in sys.argv[1:] if arg in ('close', 'shutdown')][0]
END_AFTER_MS = 3000  # the window closes, or ROS shuts down, this long after run starts


class GuiLifecycleTest(unittest.TestCase):

    def test_run_ends_with_the_window_and_with_ros(self):
        rospy.init_node('gui_R')
        app = application()
        window = Window(PuppetClient('R', ArmState()))
        # Generous time so that a loaded machine still draws frames before the end; whether the
        # rate is met is the benchmark's business, not a pass/fail test's.
        if MODE == 'close':
            QtCore.QTimer.singleShot(END_AFTER_MS, window.close)
        else:
            threading.Timer(END_AFTER_MS / 1000.0, rospy.signal_shutdown, args=('test',)).start()
        start_s = time.monotonic()
        gui_node.run(app, window, 30.0)
        elapsed_s = time.monotonic() - start_s
        self.assertLess(elapsed_s, 30.0)
        self.assertGreater(elapsed_s, 0.5 * END_AFTER_MS / 1000.0, 'run returned too early')
        self.assertGreaterEqual(window.frames, 1, 'the frame timer did not run')
        self.assertFalse(window.isVisible())
        # rospy runs on_shutdown hooks before it raises its flag: allow the other thread to finish.
        self.assertTrue(wait_until(rospy.is_shutdown, 5.0))


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'gui_lifecycle_' + MODE, GuiLifecycleTest)
