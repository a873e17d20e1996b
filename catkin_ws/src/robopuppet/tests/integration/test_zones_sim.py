#!/usr/bin/python3
"""rostest: main_sim with config/zones.yaml; the puppet would put Baxter's gripper into the
patient-head zone: Baxter stops at the boundary, teleop_state names the zone, and it follows
again when the puppet moves back. RViz's markers: the room (sim_cameras) is published, and the
zone markers highlight the zone while it holds Baxter and not after."""
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
from sensor_msgs.msg import JointState
from visualization_msgs.msg import Marker, MarkerArray

from robopuppet import baxter_description as bd, interface, shape_markers
from robopuppet.arm import zone_topics
from robopuppet.arm.joint_motion import mirror
from robopuppet.cameras import scene
from robopuppet.world import arm_capsules, obstacles, zones
from teleop_harness import Baxter, PuppetArm, calibrate, max_error
from waiting import wait_for

ZONES_FILE = bd.URDF_PATH.replace('urdf/baxter.urdf', 'config/zones.yaml')
WORLD_FILE = bd.URDF_PATH.replace('urdf/baxter.urdf', 'config/world.yaml')
BED_FILE = bd.URDF_PATH.replace('urdf/baxter.urdf', 'config/bed_obstacles.yaml')
HELD_HEAD = "'patient head' holds back Baxter's left arm"
# Baxter's left arm: the gripper 12 cm above the head zone, and a pose that puts it 12 cm in.
ABOVE_HEAD = [-0.43, -0.753, 0.206, 0.959, 0.218, 0.89, -0.307]
INTO_HEAD = [-0.377, -0.349, 0.157, 0.936, 0.196, 0.672, -0.307]


class Samples:
    """Baxter's left arm angles from every /robot/joint_states (numpy rows)."""

    def __init__(self):
        self.rows, self._lock = [], threading.Lock()
        self._names = bd.arm_joint_names('left')
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self._on, queue_size=1000)

    def _on(self, msg):
        where = dict(zip(msg.name, msg.position))
        with self._lock:
            self.rows.append([where[n] for n in self._names])

    def since(self, count):
        with self._lock:
            return np.array(self.rows[count:])


class Latest:
    """The newest MarkerArray of a topic."""

    def __init__(self, topic):
        self.array = None
        rospy.Subscriber(topic, MarkerArray, self._on, queue_size=10)

    def _on(self, msg):
        self.array = msg

    def held(self):
        """Return the texts of the highlighted zones' markers ([] none; None: nothing yet)."""
        if self.array is None:
            return None
        return [m.text for m in self.array.markers if m.ns.startswith(zone_topics.HELD_NAMESPACE)
                and m.action == Marker.ADD and m.type == Marker.TEXT_VIEW_FACING]


class ZonesSimTest(unittest.TestCase):

    def test_baxter_stops_at_the_patient_head_zone(self):
        with open(bd.URDF_PATH) as urdf:
            capsules = arm_capsules.ArmCapsules(bd.load(), urdf.read(), 'left')
        head = [z for z in zones.load_zones(ZONES_FILE) if z.name == 'patient head']
        guard = zones.ZoneGuard(capsules, head)
        self.assertGreater(guard.clearance(ABOVE_HEAD).min(), 0.05)
        self.assertLess(guard.clearance(INTO_HEAD).min(), -0.05)

        puppet, baxter, samples = PuppetArm('R'), Baxter(), Samples()
        room, zone_markers = Latest(interface.ROOM_MARKERS), Latest(interface.ZONE_HOLD_MARKERS)
        wait_for(lambda: room.array is not None, 30, 'the room markers')
        expected = shape_markers.room_shapes(scene.load_world(WORLD_FILE).shapes,
                                             obstacles.load_obstacles(BED_FILE))
        drawn = [m for m in room.array.markers if m.action == Marker.ADD]
        self.assertEqual(len(drawn), len(expected))
        self.assertTrue(all(m.header.frame_id == bd.BASE_FRAME for m in drawn))
        self.assertEqual(sorted(round(m.scale.x, 3) for m in drawn), sorted(round(
            s.size[0] if s.type == 'box' else 2 * s.radius, 3) for s in expected))
        wait_for(lambda: zone_markers.held() == [], 30, 'the zone markers, none held')
        wait_for(lambda: puppet.state() == interface.CALIBRATING, 30, 'arm_R calibrating')
        puppet.end_piece(False)
        calibrate(puppet, mirror(ABOVE_HEAD))   # Baxter's left arm mirrors puppet R
        wait_for(lambda: puppet.state() == interface.READY, 5, 'ready')
        puppet.press(interface.BUTTON_LEFT)
        try:
            wait_for(lambda: max_error(baxter.arm('left'), mirror(puppet.angles)) < 0.01, 30,
                     'left arm above the head')
        except AssertionError as error:
            raise AssertionError('%s: puppet (mirrored) %s, Baxter %s, teleop %r' % (
                error, mirror(puppet.angles), baxter.arm('left'), puppet.teleop.detail))

        start = len(samples.rows)
        puppet.hand(mirror(INTO_HEAD))
        wait_for(lambda: "keep-out zone 'patient head'" in puppet.teleop.detail, 20,
                 'teleop_state naming the zone (now %r)' % puppet.teleop.detail)
        time.sleep(3.0)   # pushing against the zone
        held = baxter.arm('left')
        self.assertGreater(max_error(held, mirror(puppet.angles)), 0.05)   # not on the puppet
        rows = samples.since(start)
        self.assertGreater(len(rows), 200)
        clearance = np.array([guard.clearance(q).min() for q in rows])
        self.assertGreater(clearance.min(), 0.0, 'Baxter measured inside the head zone')
        self.assertLess(guard.clearance(held).min(), 0.01, 'Baxter stopped short of the zone')
        detail = puppet.teleop.detail
        self.assertRegex(detail, r"held back by keep-out zone 'patient head' \(\w+\)")
        wait_for(lambda: zone_markers.held() == [HELD_HEAD], 5,
                 'the head zone highlighted (now %r)' % zone_markers.held())

        puppet.hand(mirror(ABOVE_HEAD))            # back out: Baxter follows again
        wait_for(lambda: max_error(baxter.arm('left'), mirror(puppet.angles)) < 0.01 and
                 max_error(puppet.angles, mirror(ABOVE_HEAD)) < 0.05, 30,
                 'left arm back above the head')
        wait_for(lambda: 'keep-out zone' not in puppet.teleop.detail, 5,
                 'the zone gone from teleop_state')
        wait_for(lambda: zone_markers.held() == [], 5, 'the highlight gone')


if __name__ == '__main__':
    rospy.init_node('test_zones_sim')
    rostest.rosrun('robopuppet', 'zones_sim', ZonesSimTest)
