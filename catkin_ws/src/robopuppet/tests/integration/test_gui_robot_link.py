#!/usr/bin/python3
"""The main tab's link box on the operator host: it shows the LinkState arm_R publishes (here the
test publishes it on the real topic) and turns red, "No link to the robot room", on the network
or robot side, about 1 s after it stops, while this room's real puppet (serial_R on
puppet_sim_R) stays healthy."""
import time
import unittest

import rospy
import rostest

from gui_testing import application, wait_for_subscribers, wait_until
from robopuppet import interface
from robopuppet.gui import link_view, look, main_tab
from robopuppet.gui.puppet_client import PuppetClient
from robopuppet.gui.state import ArmState
from robopuppet.gui.window import Window
from robopuppet_msgs.msg import LinkState

PUBLISH_PERIOD_S = 0.2  # arm_X publishes several times a second


class GuiRobotLinkTest(unittest.TestCase):

    def test_the_box_shows_link_state_and_turns_red_when_it_stops(self):
        rospy.init_node('gui_robot_link_test')
        application()
        client = PuppetClient('R', ArmState())
        window = Window(client, debug_mode=False)
        box = window.main_tab.link_box

        def status():
            window.frame()
            return box.status_label.text()

        def puppet_healthy():
            snap = client.state.snapshot()
            return (snap.link is not None and snap.heartbeat_s is not None
                    and link_view.puppet_problem(snap, client.now()) is None)

        self.assertTrue(wait_until(puppet_healthy, 30.0), 'serial_R never reported a puppet')
        self.assertTrue(status().startswith('No link to the robot room: nothing heard yet'),
                        status())
        publisher = rospy.Publisher('%s/%s' % (interface.puppet_ns('R'), interface.LINK_STATE),
                                    LinkState, queue_size=1)
        self.assertTrue(wait_for_subscribers([publisher]))
        msg = LinkState(rtt=0.104, clock_known=True, sample_age=0.31, max_sample_age=0.35,
                        loss=0.1, level=link_view.WARN,
                        fault=LinkState.NETWORK, detail='samples 310 ms old (limit 350 ms)')
        timer = rospy.Timer(rospy.Duration(PUBLISH_PERIOD_S), lambda _: publisher.publish(msg))
        shown = 'Network slow: samples 310 ms old (limit 350 ms)'
        self.assertTrue(wait_until(lambda: status() == shown, 10.0), status())
        self.assertIn(look.AMBER, box.status_label.styleSheet())
        self.assertEqual([box.rtt_label.text(), box.delay_label.text(), box.loss_label.text(),
                          box.where_label.text()],
                         ['Round trip: 104 ms', 'Delay to Baxter: 310 ms (limit 350 ms)',
                          'Pings lost: 10 % in the last few seconds', 'Problem: network'])
        timer.shutdown()
        stopped_s = time.monotonic()
        self.assertTrue(wait_until(lambda: status().startswith(
            'No link to the robot room: nothing heard for'), 10.0), status())
        red_after_s = time.monotonic() - stopped_s
        rospy.loginfo('red %.2f s after the last LinkState was due', red_after_s)
        # The last message came at most one period before the stop; red needs > 1 s of silence.
        self.assertGreater(red_after_s, link_view.LINK_STATE_TIMEOUT_S - PUBLISH_PERIOD_S - 0.05)
        self.assertIn(look.RED, box.status_label.styleSheet())
        self.assertTrue(puppet_healthy())
        self.assertEqual(box.where_label.text(), 'Problem: network or robot room')
        self.assertEqual(box.rtt_label.text(), 'Round trip: —')


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'gui_robot_link', GuiRobotLinkTest)
