#!/usr/bin/python3
"""rostest: Baxter's camera services on the stand-in, used as Rethink's SDK 1.2.0
CameraController and camera_control.py use them: /cameras/list within 10 s, open with
CameraSettings (the image takes the size), close (its images and topics stop), a size Baxter
has not and a third camera refused with an err code and a warning, the room camera outside the
rule."""
import errno
import threading
import time
import unittest

import rospy
import rostest
from baxter_core_msgs.msg import CameraControl, CameraSettings
from baxter_core_msgs.srv import CloseCamera, ListCameras, OpenCamera
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import CameraInfo, Image, JointState

from baxter_sim_testing import Latest
from waiting import wait_for
from robopuppet import baxter_description as bd, interface

LEFT, RIGHT, HEAD, ROOM = 'left_hand_camera', 'right_hand_camera', 'head_camera', 'room_camera'


class Frames:
    """Every raw frame of one camera: (receive time, stamp s, width, height)."""

    def __init__(self, camera):
        self.lock, self.frames = threading.Lock(), []
        rospy.Subscriber(interface.camera_topic(camera, interface.CAMERA_IMAGE), Image,
                         self._on_image, queue_size=30, buff_size=2 ** 24)

    def _on_image(self, msg):
        with self.lock:
            self.frames.append((time.monotonic(), msg.header.stamp.to_sec(), msg.width,
                                msg.height))

    def stamped_after(self, stamp_s):
        """Return [(width, height)] of the frames stamped after stamp_s (ROS time, s)."""
        with self.lock:
            return [(w, h) for _, s, w, h in self.frames if s > stamp_s]


def advertised(camera):
    """Return whether the master has a publisher of the camera's image (camera_control.py -l's
    test of an open camera)."""
    topic = interface.camera_topic(camera, interface.CAMERA_IMAGE)
    return any(name == topic for name, _ in rospy.get_published_topics())


class CameraServiceTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('camera_service_test')
        pose = {}
        for side in ('left', 'right'):
            pose.update(bd.neutral_pose(side))
        joints = rospy.Publisher(interface.ROBOT_JOINT_STATES, JointState, queue_size=1,
                                 latch=True)
        joints.publish(JointState(name=list(pose), position=list(pose.values())))
        cls.rosout = Latest('/rosout', Log)
        cls.frames = {c: Frames(c) for c in (LEFT, RIGHT, HEAD, ROOM)}
        cls.infos = {c: Latest(interface.camera_topic(c, interface.CAMERA_INFO), CameraInfo)
                     for c in (RIGHT, HEAD)}
        # What CameraController's constructor does: wait for the list service within 10 s.
        rospy.wait_for_service(interface.CAMERAS_LIST, timeout=10)
        cls.list = rospy.ServiceProxy(interface.CAMERAS_LIST, ListCameras)
        cls.open = rospy.ServiceProxy(interface.CAMERAS_OPEN, OpenCamera)
        cls.close = rospy.ServiceProxy(interface.CAMERAS_CLOSE, CloseCamera)

    def warned(self, *words):
        return any(m.name == '/sim_cameras' and m.level == Log.WARN
                   and all(w in m.msg for w in words) for _, m in self.rosout.recorded())

    def sizes_after(self, camera, stamp_s, count):
        """Wait for `count` frames of a camera stamped after stamp_s; return their sizes."""
        wait_for(lambda: len(self.frames[camera].stamped_after(stamp_s)) >= count, 30.0,
                 '%d frames of %s' % (count, camera))
        return set(self.frames[camera].stamped_after(stamp_s))

    def test_a_session_as_camera_controller_runs_it(self):
        self.rosout.record()
        # At start the hand cameras have power and stream at the node's size; the head camera
        # has no power and no topics; the room camera is not Baxter's: never listed.
        self.assertEqual(self.list().cameras, [LEFT, RIGHT])
        self.assertEqual(self.sizes_after(RIGHT, 0.0, 2), {(640, 480)})
        self.assertFalse(advertised(HEAD))

        # CameraController's own settings: 320x200 at 20 frames/s, no controls; then a control
        # as its exposure property sends it.
        settings = CameraSettings(width=320, height=200, fps=20.0)
        self.assertEqual(self.open(RIGHT, settings).err, 0)
        opened = rospy.get_time()
        self.assertEqual(self.sizes_after(RIGHT, opened, 5), {(320, 200)})
        wait_for(lambda: self.infos[RIGHT].msg.width == 320, 10.0, 'camera_info at 320x200')
        self.assertEqual((self.infos[RIGHT].msg.height, self.infos[RIGHT].msg.K[0]),
                         (200, 403.0 * 320 / 640))
        settings.controls.append(CameraControl(CameraControl.CAMERA_CONTROL_EXPOSURE, 50))
        settings.width, settings.height = 960, 600
        self.assertEqual(self.open(RIGHT, settings).err, 0)
        self.assertEqual(self.sizes_after(RIGHT, rospy.get_time(), 3), {(960, 600)})

        # A size Baxter has not: EINVAL and a warning; the camera streams on as it was.
        bad = CameraSettings(width=640, height=480, fps=20.0)
        self.assertEqual(self.open(RIGHT, bad).err, errno.EINVAL)
        wait_for(lambda: self.warned('640x480', RIGHT), 10.0, 'a warning about 640x480')
        self.assertEqual(self.sizes_after(RIGHT, rospy.get_time(), 3), {(960, 600)})

        # The third camera: refused (ENODEV, a warning), and neither hand camera closed.
        head = CameraSettings(width=640, height=400, fps=20.0)
        self.assertEqual(self.open(HEAD, head).err, errno.ENODEV)
        wait_for(lambda: self.warned(HEAD, 'no power'), 10.0, 'a warning about the third')
        now = rospy.get_time()
        self.sizes_after(LEFT, now, 3)
        self.sizes_after(RIGHT, now, 3)
        self.assertFalse(advertised(HEAD))

        # Close the left hand camera: no frame of it stamped after the answer, while the right
        # one goes on; its topics are gone; its power went to the head camera.
        self.assertEqual(self.close(LEFT).err, 0)
        closed = rospy.get_time()
        self.sizes_after(RIGHT, closed, 15)
        self.assertEqual(self.frames[LEFT].stamped_after(closed), [])
        self.assertFalse(advertised(LEFT))
        self.assertEqual(self.list().cameras, [RIGHT, HEAD])
        self.assertEqual(self.close(LEFT).err, errno.EINVAL)  # CameraController.close's "fine"

        # Now the head camera opens (upright: camera_info's negative focal length), and the
        # left one has no power until another closes.
        self.assertEqual(self.open(HEAD, head).err, 0)
        self.assertEqual(self.sizes_after(HEAD, rospy.get_time(), 3), {(640, 400)})
        wait_for(lambda: self.infos[HEAD].msg, 10.0, "the head camera's camera_info")
        self.assertEqual(self.infos[HEAD].msg.K[0], -410.0)
        self.assertEqual(self.open(LEFT, head).err, errno.ENODEV)

        # The room camera streams beside the two Baxter cameras: not part of their rule.
        self.sizes_after(ROOM, rospy.get_time(), 3)

    def test_names_that_are_not_baxters_cameras_are_refused(self):
        self.rosout.record()
        settings = CameraSettings(width=640, height=400, fps=20.0)
        for name in (ROOM, 'nose_camera'):
            self.assertEqual(self.open(name, settings).err, errno.ENODEV)
            self.assertEqual(self.close(name).err, errno.ENODEV)
            wait_for(lambda: self.warned(name), 10.0, 'a warning about ' + name)
        self.assertNotIn(ROOM, self.list().cameras)


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'camera_service', CameraServiceTest)
