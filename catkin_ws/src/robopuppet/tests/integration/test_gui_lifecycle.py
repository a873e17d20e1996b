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
FRAMES_FIRST = 3  # the window closes, or ROS shuts down, once it has drawn this many frames


class GuiLifecycleTest(unittest.TestCase):

    def test_run_ends_with_the_window_and_with_ros(self):
        rospy.init_node('gui_R')
        app = application()
        window = Window(PuppetClient('R', ArmState()))
        ended = []  # when the end was triggered (time.monotonic())

        def drawn():
            return window.frames >= FRAMES_FIRST

        if MODE == 'close':
            def close_once_drawn():  # as the operator would, on the GUI thread
                if drawn() and not ended:
                    ended.append(time.monotonic())
                    window.close()
            poll = QtCore.QTimer()
            poll.timeout.connect(close_once_drawn)
            poll.start(20)
        else:
            def shut_down():  # from another thread, as roslaunch or rosnode kill would
                deadline = time.monotonic() + 20.0
                while not drawn() and time.monotonic() < deadline:
                    time.sleep(0.02)
                ended.append(time.monotonic())
                rospy.signal_shutdown('test')
            threading.Thread(target=shut_down, daemon=True).start()
        start_s = time.monotonic()
        gui_node.run(app, window, 30.0)
        returned_s = time.monotonic()
        self.assertLess(returned_s - start_s, 30.0)
        self.assertTrue(ended and ended[0] <= returned_s, 'run returned before the end')
        self.assertGreaterEqual(window.frames, FRAMES_FIRST, 'the frame timer did not run')
        self.assertFalse(window.isVisible())
        # rospy runs on_shutdown hooks before it raises its flag: allow the other thread to finish.
        self.assertTrue(wait_until(rospy.is_shutdown, 5.0))


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'gui_lifecycle_' + MODE, GuiLifecycleTest)
