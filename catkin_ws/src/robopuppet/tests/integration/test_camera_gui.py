#!/usr/bin/python3
"""The GUI's Cameras tab with the real camera node: it shows the frames, flags a stalled stream
amber then red, survives a corrupt JPEG, and subscribes to nothing while hidden."""
import os
import shutil
import unittest

import rosgraph
import rospy
import rostest
from sensor_msgs.msg import CompressedImage

from gui_testing import application, wait_for_subscribers, wait_until
from robopuppet import interface
from robopuppet.gui import camera_view
from robopuppet.gui.camera_client import CameraClient
from robopuppet.gui.look import AMBER, GREEN, RED
from robopuppet.gui.puppet_client import PuppetClient
from robopuppet.gui.state import ArmState
from robopuppet.gui.window import Window
from test_camera_node import write_video

CAMERA, BAD_CAMERA = 'test_camera', 'bad_camera'


def subscribers(camera):
    """Return the nodes the master lists as subscribers of a camera's image/compressed."""
    topic = interface.camera_topic(camera, interface.CAMERA_COMPRESSED)
    _, subs, _ = rosgraph.Master(rospy.get_name()).getSystemState()
    return dict((t, nodes) for t, nodes in subs).get(topic, [])


class CameraGuiTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('gui_R')
        cls.device = rospy.get_param('~device')
        os.makedirs(os.path.dirname(cls.device), exist_ok=True)
        write_video(cls.device)
        application()
        cls.window = Window(PuppetClient('R', ArmState()), debug_mode=False,
                            cameras=CameraClient())
        cls.pane = cls.window.camera_pane
        cls.window.show()

    @classmethod
    def tearDownClass(cls):
        cls.window.close()
        shutil.rmtree(os.path.dirname(cls.device), ignore_errors=True)

    def frames_until(self, predicate, timeout_s):
        """Draw frames (as the window's timer does) until predicate() holds; return it."""
        def drawn():
            self.window.frame()
            return predicate()
        return wait_until(drawn, timeout_s, step_s=0.03)

    def level(self):
        return self.pane.verdict().level

    def test_the_tab_shows_flags_and_unsubscribes(self):
        me = rospy.get_name()
        # Hidden (another tab shows): no subscription.
        self.window.tabs.setCurrentWidget(self.window.calibration_tab)
        self.frames_until(lambda: False, 1.0)
        self.assertNotIn(me, subscribers(CAMERA))
        # Shown (the main tab, beside the status): it finds the camera on the master,
        # subscribes and draws its frames.
        self.window.tabs.setCurrentWidget(self.window.main_tab)
        self.assertTrue(self.frames_until(lambda: self.pane.view.has_image(), 20.0),
                        'no frame shown: %s' % self.pane.status.text())
        self.assertEqual(self.pane.camera, CAMERA)
        self.assertIn(me, subscribers(CAMERA))
        self.assertTrue(self.frames_until(lambda: GREEN in self.pane.status.styleSheet(), 5.0),
                        self.pane.status.text())
        self.assertIn('320×240', self.pane.status.text())
        image = self.pane.view.grab().toImage()
        rect = self.pane.view.target_rect()
        top_left = image.pixelColor(rect.left() + rect.width() // 8,
                                    rect.top() + rect.height() // 8)
        self.assertGreater(top_left.red(), 200)  # the video's red quadrant
        self.assertLess(top_left.green() + top_left.blue(), 80)
        self.assertTrue(self.frames_until(lambda: len(self.pane.view.display_ages_s) > 5, 5.0))
        self.assertLess(max(self.pane.view.display_ages_s), 1.0)  # publish-to-display age
        # Stalled: the device goes away; amber, then red (as drawn: verdict() is computed
        # afresh, so it can turn between a frame and the check).
        os.rename(self.device, self.device + '.away')
        self.assertTrue(self.frames_until(lambda: AMBER in self.pane.status.styleSheet(), 5.0),
                        self.pane.status.text())
        self.assertIn(self.level(), (camera_view.WARN, camera_view.ERROR))
        self.assertTrue(self.frames_until(lambda: RED in self.pane.status.styleSheet(), 5.0),
                        self.pane.status.text())
        self.assertEqual(self.level(), camera_view.ERROR)
        self.assertIn('stopped', self.pane.status.text())
        # Corrupt JPEGs on another camera: counted, the GUI goes on.
        bad = rospy.Publisher(interface.camera_topic(BAD_CAMERA, interface.CAMERA_COMPRESSED),
                              CompressedImage, queue_size=10)
        self.pane.choose(BAD_CAMERA)
        self.assertTrue(wait_for_subscribers([bad]))
        self.assertNotIn(me, subscribers(CAMERA))
        for _ in range(3):
            bad.publish(CompressedImage(format='jpeg', data=b'\xff\xd8 not really a jpeg'))
            rospy.sleep(0.05)
        self.assertTrue(self.frames_until(lambda: 'undecodable' in self.pane.status.text(),
                                          5.0), self.pane.status.text())
        frames = self.window.frames
        self.frames_until(lambda: self.window.frames >= frames + 5, 2.0)
        self.assertGreaterEqual(self.window.frames, frames + 5)
        # Hidden again: unsubscribed.
        self.window.tabs.setCurrentWidget(self.window.calibration_tab)
        self.assertTrue(wait_until(lambda: me not in subscribers(BAD_CAMERA), 5.0))


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'camera_gui', CameraGuiTest)
