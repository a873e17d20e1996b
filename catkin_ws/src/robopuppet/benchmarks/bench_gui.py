#!/usr/bin/python3
"""Frames drawn per second by the GUI with all seven joints fed at 100 Hz, and its CPU share.

Usage (needs a display, e.g. under xvfb-run):
    xvfb-run -a -s '-screen 0 1920x1080x24' benchmarks/bench_gui.py [--seconds 10] [--rate 100]
        [--ros]

Without --ros (no ROS master needed) a feeder thread plays the ROS callbacks: every 1/rate s it
writes angle, voltage and encoder status of all seven joints and a heartbeat into the ArmState.
With --ros (needs a roscore at ROS_MASTER_URI) the GUI uses the real PuppetClient, and a child
process publishes the same at the rate on the seven joints' angle, voltage and enc_stat topics
and the heartbeat topic (22 messages per period: 2200 messages/s at 100 Hz), so rospy's message
handling counts in the GUI's CPU share. The arm is in hold mode, so the setpoint curves are
drawn too. The window has its default size. For each case the script prints frames per second (frame() calls,
each draining the buffers and redrawing the visible tab), Paint events per second of that tab's
plot or table, and the process CPU time per wall second (100 % = one core). Cases: a joint tab
at 30 Hz (the default ~frame_rate), the same tab unthrottled (the most this machine can draw),
the main tab at 30 Hz, and the feed alone (the part of the CPU figures that is the callbacks).
"""
import argparse
import math
import signal
import subprocess
import sys
import tempfile
import threading
import time

import rospy
from PyQt5 import QtCore, QtWidgets
from std_msgs.msg import Empty, Float32, String

from bench_support import measure_frames
from robopuppet import interface, settings
from robopuppet.gui.puppet_client import ConfigUnavailable, PuppetClient
from robopuppet.gui.state import ArmState
from robopuppet.gui.window import Window


class BenchClient:
    """Just enough of PuppetClient for drawing: state, clock, side; sends go nowhere."""

    side = 'R'

    def __init__(self):
        self.state = ArmState()

    @staticmethod
    def now():
        return time.monotonic()

    def set_opmode(self, opmode):
        pass

    def get_config(self, joint):
        raise ConfigUnavailable('benchmark: no config node')

    @staticmethod
    def recording_status():
        return None  # no recorder: the Recording box shows that

    @staticmethod
    def episodes_dir():
        return tempfile.gettempdir()

    def stop_replay(self):
        pass


def feed(arm, rate_hz, stop):
    """Write all joints at rate_hz until stop is set (the ROS callbacks' load)."""
    period_s = 1.0 / rate_hz
    next_s = time.monotonic()
    while not stop.is_set():
        now_s = time.monotonic()
        for joint in settings.JOINTS:
            arm.on_angle(joint, math.sin(now_s + joint), now_s)
            arm.on_voltage(joint, 5.0 * math.sin(3.0 * now_s + joint), now_s)
            arm.on_status(joint, interface.WORKING)
        arm.on_heartbeat(now_s)
        next_s += period_s
        stop.wait(max(0.0, next_s - time.monotonic()))


def publish(rate_hz):
    """Publish all joints' angle, voltage and status at rate_hz, as serial_R would, until killed."""
    rospy.init_node('bench_gui_feed', anonymous=True)
    pubs = [[rospy.Publisher(interface.joint_topic('R', joint, topic), kind, queue_size=10)
             for topic, kind in (('angle', Float32), ('voltage', Float32), ('enc_stat', String))]
            for joint in settings.JOINTS]
    heartbeat = rospy.Publisher('%s/%s' % (interface.puppet_ns('R'), interface.HEARTBEAT), Empty,
                                queue_size=1)
    rate = rospy.Rate(rate_hz)
    while not rospy.is_shutdown():
        now_s = time.monotonic()
        for joint, (angle, voltage, status) in enumerate(pubs):
            angle.publish(math.sin(now_s + joint))
            voltage.publish(5.0 * math.sin(3.0 * now_s + joint))
            status.publish(interface.WORKING)
        heartbeat.publish()
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break


def start_ros_feed(client, rate_hz):
    """Start the publishing child process; return it once the GUI receives all joints."""
    rospy.init_node('bench_gui', anonymous=True)
    child = subprocess.Popen([sys.executable, __file__, '--publish', '--rate', str(rate_hz)])
    end_s = time.monotonic() + 30.0
    while any(math.isnan(j.angle_rad) for j in client.state.snapshot().joints):
        if time.monotonic() > end_s or child.poll() is not None:
            child.kill()
            raise SystemExit('bench_gui: no joint data from the publishing process')
        time.sleep(0.1)
    return child


class PaintCounter(QtCore.QObject):
    """Count Paint events of one widget."""

    def __init__(self):
        super().__init__()
        self.count = 0

    def eventFilter(self, watched, event):
        if event.type() == QtCore.QEvent.Paint:
            self.count += 1
        return False


def run_case(window, tab, painted_widget, interval_ms, seconds):
    """Show `tab`, run the frame timer at interval_ms (None: no frames) for `seconds`.

    Returns:
        (frames/s: frame() calls, paints/s of painted_widget, CPU % of one core).
    """
    window.tabs.setCurrentWidget(tab)
    counter = PaintCounter()
    painted_widget.installEventFilter(counter)
    fps, cpu, wall_s = measure_frames(window, interval_ms, seconds, 1.0,
                                      reset=lambda: setattr(counter, 'count', 0))
    painted_widget.removeEventFilter(counter)
    return fps, counter.count / wall_s, cpu


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seconds', type=float, default=10.0, help='length of each case')
    parser.add_argument('--rate', type=float, default=100.0, help='feed rate per joint, Hz')
    parser.add_argument('--ros', action='store_true', help='feed through real ROS topics')
    parser.add_argument('--publish', action='store_true', help=argparse.SUPPRESS)
    args = parser.parse_args(rospy.myargv()[1:])
    if args.publish:
        publish(args.rate)
        return
    app = QtWidgets.QApplication(['bench_gui'])
    if args.ros:
        client = PuppetClient('R', ArmState(), clock=time.monotonic)
        child = start_ros_feed(client, args.rate)
    else:
        client = BenchClient()
        stop = threading.Event()
        feeder = threading.Thread(target=feed, args=(client.state, args.rate, stop), daemon=True)
        feeder.start()
    window = Window(client, debug_mode=True)
    window.show()
    client.state.on_opmode(interface.HOLD, time.monotonic())
    joint = window.joint_tabs[3]
    size = window.size()
    print('window %dx%d, 7 joints fed at %.0f Hz (angle + voltage + enc_stat, and the '
          'heartbeat) %s, %.0f s per case, '
          'platform %s' % (size.width(), size.height(), args.rate,
                           'over ROS topics' if args.ros else 'by a thread', args.seconds,
                           app.platformName()))
    cases = [('joint tab, frame_rate 30 Hz', joint, joint.angle_plot.viewport(), 33),
             ('joint tab, unthrottled', joint, joint.angle_plot.viewport(), 0),
             ('main tab, frame_rate 30 Hz', window.main_tab,
              window.main_tab.joint_table.viewport(), 33),
             ('feed alone (no frames)', joint, joint.angle_plot.viewport(), None)]
    for name, tab, painted, interval_ms in cases:
        fps, paints, cpu = run_case(window, tab, painted, interval_ms, args.seconds)
        print('%-30s %6.1f frames/s (%6.1f paints/s)   CPU %5.1f %% of one core'
              % (name, fps, paints, cpu))
    if args.ros:
        child.send_signal(signal.SIGINT)
        child.wait()
        rospy.signal_shutdown('benchmark done')
    else:
        stop.set()
        feeder.join()
    window.close()


if __name__ == '__main__':
    main()
