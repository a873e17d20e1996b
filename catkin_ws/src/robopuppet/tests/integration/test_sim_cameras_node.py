#!/usr/bin/python3
"""rostest: the stand-in's simulated right hand camera renders only while watched, its frames
change while the arm moves (through Baxter's API) and stay the same while it holds still,
garbage joint states change nothing, and image, JPEG and CameraInfo agree on size."""
import threading
import time
import unittest

import cv2
import numpy as np
import rospy
import rostest
from baxter_core_msgs.msg import JointCommand
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import CameraInfo, CompressedImage, Image, JointState
from std_msgs.msg import Bool

from baxter_sim_testing import Latest, publisher
from waiting import wait_for
from robopuppet import interface
from robopuppet.cameras import jpeg

CAMERA = 'right_hand_camera'
MOVE = {'right_w1': 0.4, 'right_w2': 0.6}  # rad added to the held pose


class Frames:
    """Raw frames of one camera topic, with receive times (a subscription made on start())."""

    def __init__(self, camera):
        self.camera, self.lock, self.frames, self.sub = camera, threading.Lock(), [], None

    def start(self):
        self.sub = rospy.Subscriber(interface.camera_topic(self.camera, interface.CAMERA_IMAGE),
                                    Image, self._on_image, queue_size=30, buff_size=2 ** 24)

    def _on_image(self, msg):
        with self.lock:
            self.frames.append((time.monotonic(), msg))

    def since(self, start_s):
        with self.lock:
            return [msg for t, msg in self.frames if t >= start_s]


class SimCamerasTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('sim_cameras_test')
        cls.joints = Latest(interface.ROBOT_JOINT_STATES, JointState)
        cls.infos = {c: Latest(interface.camera_topic(c, interface.CAMERA_INFO), CameraInfo)
                     for c in (CAMERA, interface.ROOM_CAMERA)}
        cls.rosout = Latest('/rosout', Log)
        cls.enable_pub = publisher(interface.SET_SUPER_ENABLE, Bool)
        cls.cmd_pub = publisher(interface.limb_topic('right', 'joint_command'), JointCommand)
        wait_for(lambda: cls.joints.msg is not None, 20.0, 'the stand-in to publish')

    def positions(self):
        """Return the stand-in's newest joint positions (not this test's garbage ones)."""
        def full():
            msg = self.joints.msg
            return len(msg.name) == len(msg.position) and set(MOVE) <= set(msg.name)
        wait_for(full, 10.0, "the stand-in's joint states")
        msg = self.joints.msg
        return dict(zip(msg.name, msg.position))

    def still_frames(self, frames, count=5):
        """Return the first `count` raw frames that arrive from now on (the node runs at nice
        +10: on a loaded machine they may come slower than 15 Hz)."""
        start = time.monotonic()
        wait_for(lambda: len(frames.since(start)) >= count, 20.0, '%d frames' % count)
        return frames.since(start)[:count]

    def test_frames_follow_the_arm_and_only_the_arm(self):
        # Nobody watches an image yet (this test subscribes camera_info only): nothing renders.
        time.sleep(2.0)
        self.assertIsNone(self.infos[CAMERA].msg)
        self.assertIsNone(self.infos[interface.ROOM_CAMERA].msg)
        self.enable_pub.publish(Bool(True))
        frames = Frames(CAMERA)
        frames.start()
        compressed = Latest(interface.camera_topic(CAMERA, interface.CAMERA_COMPRESSED),
                            CompressedImage)
        wait_for(lambda: frames.since(0.0) and compressed.msg, 30.0, 'the first frames')
        # The room camera is still not watched: still not rendered.
        self.assertIsNone(self.infos[interface.ROOM_CAMERA].msg)

        # What comes out: 640x480 bgr8, a JPEG of the same size at quality 80, the CameraInfo
        # of Baxter's hand camera in its URDF frame.
        image, packed, info = frames.since(0.0)[-1], compressed.msg, self.infos[CAMERA].msg
        self.assertEqual((image.width, image.height, image.encoding, image.step),
                         (640, 480, 'bgr8', 640 * 3))
        self.assertEqual((info.width, info.height), (640, 480))
        self.assertEqual(info.K[0], 403.0)
        self.assertEqual(image.header.frame_id, 'right_hand_camera')
        self.assertEqual(info.header.frame_id, 'right_hand_camera')
        self.assertEqual(packed.format, jpeg.JPEG_FORMAT)
        decoded = cv2.imdecode(np.frombuffer(packed.data, np.uint8), cv2.IMREAD_COLOR)
        self.assertEqual(decoded.shape, (480, 640, 3))
        self.assertEqual(jpeg.quality_of(packed.data), 80)

        # Holding still: every frame the same.
        held = self.still_frames(frames)
        self.assertEqual(len({f.data for f in held}), 1, 'frames change while the arm is still')
        before = held[-1].data

        # Garbage on /robot/joint_states: warned about, and no frame changes.
        garbage = rospy.Publisher(interface.ROBOT_JOINT_STATES, JointState, queue_size=10)
        wait_for(lambda: garbage.get_num_connections() > 0, 10.0, 'subscribers of garbage')
        self.rosout.record()
        start = time.monotonic()
        while time.monotonic() - start < 1.5:
            garbage.publish(JointState(name=['right_w2', 'right_w1'], position=[float('nan')]))
            garbage.publish(JointState(name=['right_w2'], position=[float('inf')]))
            time.sleep(0.005)
        wait_for(lambda: any(m.name == '/sim_cameras' and 'ignored' in m.msg
                             for _, m in self.rosout.recorded()), 10.0,
                 'a warning about the garbage')
        wait_for(lambda: frames.since(start), 20.0, 'frames while garbage came in')
        self.assertEqual({f.data for f in frames.since(start)}, {before})

        # Moving the right arm through Baxter's API: the frames change.
        held_pose = self.positions()
        targets = {name: held_pose[name] + delta for name, delta in MOVE.items()}
        command = JointCommand(mode=JointCommand.POSITION_MODE, names=list(targets),
                               command=list(targets.values()))
        start = time.monotonic()
        while not all(abs(self.positions()[n] - v) < 0.01 for n, v in targets.items()):
            self.assertLess(time.monotonic() - start, 20.0, 'the arm did not reach the target')
            self.cmd_pub.publish(command)
            time.sleep(0.02)
        wait_for(lambda: {f.data for f in frames.since(start)} - {before}, 20.0,
                 'a frame showing the arm moved')

        # Holding still again (commands stopped, the stand-in holds): one new frame.
        time.sleep(0.5)
        held = self.still_frames(frames)
        self.assertEqual(len({f.data for f in held}), 1, 'frames change while the arm is still')
        self.assertNotEqual(held[-1].data, before)
        self.assertIsNone(self.infos[interface.ROOM_CAMERA].msg)


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'sim_cameras', SimCamerasTest)
