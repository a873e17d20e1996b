#!/usr/bin/python3
"""Camera pane: publish-to-display age (p50/p99) and the GUI's CPU with one and three cameras.

Usage (needs a display, e.g. under xvfb-run; starts its own roscore on a free port):
    xvfb-run -a -s '-screen 0 1920x1080x24' benchmarks/bench_camera_gui.py [--seconds 10]
        [--camera-rate 30] [--joint-rate 100]

Child processes publish three test cameras (640x480 JPEG of a moving scene with noise, quality 80,
~41 kB, stamped when published) on /cameras/bench_N/image/compressed at --camera-rate, and all seven
joints of arm R at --joint-rate as serial_R would (bench_gui.py --publish), so the joint tabs'
live plots are fed through rospy as in use. The GUI is the real Window with the real
PuppetClient and CameraClient, at its default size, its frame timer at 30 Hz (~frame_rate).
Age: now minus the image's header stamp when the pane first paints the image (publish, rospy,
decode on the callback thread, wait for the frame timer, scale and paint). CPU: the GUI process's
CPU time per wall second (100 % = one core), rospy's threads and the JPEG decoding included.
Targets: p99 age <= 100 ms locally; one camera pane plus the live plots <= 50 %.
"""
import argparse
import math
import os
import subprocess
import sys
import time

import cv2
import numpy as np
import rospy
from PyQt5 import QtWidgets
from sensor_msgs.msg import CompressedImage

from bench_support import measure_frames, percentile, private_roscore
from robopuppet import interface
from robopuppet.gui.camera_client import CameraClient
from robopuppet.gui.camera_pane import CameraPane
from robopuppet.gui.puppet_client import PuppetClient
from robopuppet.gui.state import ArmState
from robopuppet.gui.window import Window

CAMERAS = ('bench_0', 'bench_1', 'bench_2')
SIZE = (640, 480)
QUALITY = 80
FRAME_INTERVAL_MS = 33  # the GUI's default ~frame_rate, 30 Hz
HERE = os.path.dirname(os.path.abspath(__file__))


def scene(index, width=SIZE[0], height=SIZE[1]):
    """Return frame `index` of a test scene: gradients with a webcam's sensor noise, a moving
    disc and the frame number."""
    y, x = np.indices((height, width))
    noise = np.random.default_rng(index).integers(-12, 13, (height, width, 3))
    image = np.clip(np.stack([x * 255 // width, y * 255 // height,
                              np.full((height, width), 90)], axis=2) + noise, 0, 255)
    image = image.astype(np.uint8)
    angle = index * 0.2
    centre = (int(width / 2 + 150 * math.cos(angle)), int(height / 2 + 100 * math.sin(angle)))
    cv2.circle(image, centre, 60, (40, 40, 230), -1)
    cv2.putText(image, 'frame %d' % index, (20, 60), cv2.FONT_HERSHEY_SIMPLEX, 1.5,
                (255, 255, 255), 3)
    return image


def publish_cameras(rate_hz):
    """Publish the test cameras at rate_hz until killed (a child process)."""
    rospy.init_node('bench_cameras', anonymous=True)
    frames = [cv2.imencode('.jpg', scene(i), [cv2.IMWRITE_JPEG_QUALITY, QUALITY])[1].tobytes()
              for i in range(32)]
    pubs = [rospy.Publisher(interface.camera_topic(name, interface.CAMERA_COMPRESSED),
                            CompressedImage, queue_size=1) for name in CAMERAS]
    rate, index = rospy.Rate(rate_hz), 0
    while not rospy.is_shutdown():
        for pub in pubs:
            msg = CompressedImage(format='jpeg', data=frames[index % len(frames)])
            msg.header.stamp = rospy.Time.now()
            pub.publish(msg)
        index += 1
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break


def run_case(window, tab, panes, seconds):
    """Show `tab` and the extra `panes`, draw at 30 Hz for `seconds`.

    Returns:
        (images drawn per second over all panes, [age s], CPU % of one core, frames/s)
    """
    window.tabs.setCurrentWidget(tab)
    for pane in panes:
        pane.show()
    watched = list(panes) + ([window.camera_pane] if tab is window.main_tab else [])

    def reset():
        for pane in watched:
            pane.view.display_ages_s.clear()
    fps, cpu, wall_s = measure_frames(  # 2 s of warm-up: subscribe, find the cameras
        window, FRAME_INTERVAL_MS, seconds, 2.0, [pane.refresh for pane in panes], reset)
    ages = [age for pane in watched for age in pane.view.display_ages_s]
    for pane in panes:
        pane.hide()
    return len(ages) / wall_s, ages, cpu, fps


def start_children(camera_rate_hz, joint_rate_hz):
    return [subprocess.Popen([sys.executable, __file__, '--publish-cameras',
                              '--camera-rate', str(camera_rate_hz)]),
            subprocess.Popen([sys.executable, os.path.join(HERE, 'bench_gui.py'), '--publish',
                              '--rate', str(joint_rate_hz)])]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seconds', type=float, default=10.0, help='length of each case')
    parser.add_argument('--camera-rate', type=float, default=30.0, help='frames/s per camera')
    parser.add_argument('--joint-rate', type=float, default=100.0, help='joint feed rate, Hz')
    parser.add_argument('--publish-cameras', action='store_true', help=argparse.SUPPRESS)
    args = parser.parse_args(rospy.myargv()[1:])
    if args.publish_cameras:
        publish_cameras(args.camera_rate)
        return
    with private_roscore('bench_camera_gui_'):
        children = start_children(args.camera_rate, args.joint_rate)
        try:
            bench(args)
        finally:
            for child in children:
                child.terminate()
                child.wait(10)


def bench(args):
    app = QtWidgets.QApplication(['bench_camera_gui'])
    rospy.init_node('bench_camera_gui', anonymous=True)
    client = PuppetClient('R', ArmState())
    window = Window(client, debug_mode=True, cameras=CameraClient())
    window.show()
    end_s = time.monotonic() + 30.0
    while any(math.isnan(j.angle_rad) for j in client.state.snapshot().joints):
        if time.monotonic() > end_s:
            raise SystemExit('bench_camera_gui: no joint data from the publishing process')
        app.processEvents()
        time.sleep(0.05)
    window.camera_pane.choose(CAMERAS[0])
    extra = []  # camera panes in windows of their own (as a dock would show them)
    for name in CAMERAS:
        pane = CameraPane(CameraClient())
        pane.resize(640, 520)
        pane.setWindowTitle('camera %s' % name)
        pane.choose(name)
        extra.append(pane)
    size = window.size()
    print('window %dx%d, %d test cameras %dx%d JPEG q%d at %.0f frames/s, joints fed at %.0f '
          'Hz over ROS, frames drawn at %.0f Hz, %.0f s per case, platform %s'
          % (size.width(), size.height(), len(CAMERAS), SIZE[0], SIZE[1], QUALITY,
             args.camera_rate, args.joint_rate, 1000.0 / FRAME_INTERVAL_MS, args.seconds,
             app.platformName()))
    joint = window.joint_tabs[3]
    cases = [('calibration tab, camera hidden', window.calibration_tab, []),
             ('main tab and its camera', window.main_tab, []),
             ('joint tab plots, no camera', joint, []),
             ('joint tab plots + 1 camera pane', joint, extra[:1]),
             ('joint tab plots + 3 camera panes', joint, extra)]
    for name, tab, panes in cases:
        drawn, ages, cpu, fps = run_case(window, tab, panes, args.seconds)
        if ages:
            age = 'age p50 %5.1f ms  p99 %5.1f ms  max %5.1f ms' % tuple(
                1000.0 * value for value in (percentile(ages, 0.5), percentile(ages, 0.99),
                                             max(ages)))
        else:
            age = 'no camera image drawn'
        print('%-34s %5.1f frames/s  %5.1f images/s  %s  CPU %5.1f %% of one core'
              % (name, fps, drawn, age, cpu))
    for pane in extra:
        pane.close()
    window.close()
    rospy.signal_shutdown('benchmark done')


if __name__ == '__main__':
    main()
