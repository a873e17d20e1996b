"""A mixin for the calibration wizard's rostests: arm R's window on the simulated puppet."""
import os
import shutil

import rospy

from gui_testing import application, wait_until
from robopuppet.gui.puppet_client import PuppetClient, SimPuppetClient
from robopuppet.gui.state import ArmState
from robopuppet.gui.window import Window


class CalibrationWindow:
    """unittest.TestCase mixin: open_window() in setUpClass gives client, sim, window and tab
    (the calibration tab), and removes the test's temporary ini (~ini_path) at the end."""

    @classmethod
    def open_window(cls):
        application()
        cls.ini_path = rospy.get_param('~ini_path')
        cls.addClassCleanup(shutil.rmtree, os.path.dirname(cls.ini_path), True)
        cls.client = PuppetClient('R', ArmState())
        cls.sim = SimPuppetClient('R')
        cls.window = Window(cls.client, debug_mode=False, sim=cls.sim)
        cls.tab = cls.window.calibration_tab

    def until(self, predicate, timeout_s=30.0):
        """Draw frames until predicate() is true or timeout_s passed; return its last value."""
        def frame_and_check():
            self.window.frame()
            return predicate()
        return wait_until(frame_and_check, timeout_s)
