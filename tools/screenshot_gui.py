#!/usr/bin/python3
"""Drive the real GUI against the running simulated system and save three screenshots.

Usage: tools/screenshot_gui.py OUT_DIR (started by tools/screenshot_gui.sh, which also starts the
simulated system). Builds the same window as gui_R (PuppetClient, CameraClient for the main tab's
camera pane, virtual puppet panel), then, like an operator: sweeps the quadrature joints through
their index marks with the panel's sliders until all seven encoders work, makes joint 1 a P
controller (pid_kp 4 V/rad, no I or D) with the joint tab's Set, presses button 3 (Baxter's right
arm follows) and button 1 (hold), and waves joint 1 with its slider. Saves OUT_DIR/gui_main.png
(main tab) and OUT_DIR/gui_joint1.png (joint 1 tab). Then presses button 1 again (limp), moves the
sliders over REACH_S to REACH_POSE_RAD, so that Baxter's right arm reaches out over the bed with its
hand camera above the patient, waits until /robot/joint_states shows the arm there (pressing button
3 again whenever following stopped, as a busy machine's puppet timeouts can make it), shows the main
tab's camera on right_hand_camera and saves OUT_DIR/gui_camera_reach.jpg once the pane judges the
stream live and shows at least CAMERA_RATE_HZ frames/s. Exits with status 1, saving nothing more,
when a step does not happen within a minute or Set is not confirmed.
"""
import math
import os
import sys
import threading
import time

import rospy
from PyQt5 import QtCore, QtWidgets
from sensor_msgs.msg import JointState

from robopuppet import baxter_description, interface
from robopuppet.gui import camera_view
from robopuppet.gui.camera_client import CameraClient
from robopuppet.gui.puppet_client import PuppetClient, SimPuppetClient
from robopuppet.gui.state import ArmState
from robopuppet.gui.window import Window

WAVED_JOINT = 1
STEP_TIMEOUT_S = 60.0
# Puppet R = Baxter's right arm, joints s0 s1 e0 e1 w0 w1 w2 (rad): the hand out over the bed,
# its camera 0.8 m above the mattress looking down at the whole patient, head at the top of the
# image (found with baxter_description's forward kinematics and the simulated camera's frames),
# every joint inside the puppet's default angle limits of +-1.571 rad.
REACH_POSE_RAD = (0.82, -1.45, 0.0, 1.45, 0.58, 1.13, -1.31)
REACH_S = 6.0  # the sliders move from where they are to REACH_POSE_RAD in this time
REACHED_RAD = 0.02  # Baxter's right arm is there when every joint is this close
CAMERA = 'right_hand_camera'  # one of interface.BAXTER_CAMERAS
CAMERA_RATE_HZ = 14.0  # the shot waits for the pane to show this many frames/s (of 15)
CAMERA_SHOT_WIDTH = 1024  # pixels; the JPEG of the camera shot is scaled to this width (~60 kB)
JPEG_QUALITY = 85


class GaveUp(Exception):
    """The scenario cannot go on; str() says why."""


class BaxterRightArm:
    """The newest positions of Baxter's right arm from /robot/joint_states (rospy thread)."""

    NAMES = baxter_description.arm_joint_names('right')

    def __init__(self):
        self._lock = threading.Lock()
        self._positions = {}
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self._on_state, queue_size=1)

    def _on_state(self, msg):
        with self._lock:
            self._positions.update(zip(msg.name, msg.position))

    def positions(self):
        """Return the seven newest positions (rad), None for a joint not heard of."""
        with self._lock:
            return [self._positions.get(name) for name in self.NAMES]

    def near(self, target_rad, tolerance_rad):
        """Return True when every joint is within tolerance_rad of target_rad."""
        positions = self.positions()
        return None not in positions and all(
            abs(p - t) <= tolerance_rad for p, t in zip(positions, target_rad))


def scenario(window, out_dir, hand, baxter):
    """Yield seconds to wait (or a predicate to wait for) between the operator's actions.

    hand: a list holding at most one function of time (s) that moves the panel's sliders.
    """
    panel, client = window.sim_panel, window.client
    working = lambda: all(j.status == interface.WORKING for j in client.state.snapshot().joints)  # noqa
    yield lambda: client.state.snapshot().heartbeat_s is not None and window.sim.connected()
    for joint in (0, 2, 4, 6):  # quadrature encoders calibrate at their index mark (0 rad)
        for angle in (-0.6, 0.6, 0.2):
            panel.set_angle(joint, angle)
            yield 0.7
    yield working
    tab = window.joint_tabs[WAVED_JOINT]
    tab.get()
    yield lambda: not tab.busy()
    for name, value in (('pid_kp', '4'), ('pid_ki', '0'), ('pid_kd', '0')):  # P only
        tab.fields[name].setText(value)
    tab.set()
    yield lambda: not tab.busy()
    if not tab.message.text().startswith(('saved', 'no change')):
        raise GaveUp('Set of joint %d: %s' % (WAVED_JOINT, tab.message.text()))
    for button in (3, 1):  # right arm follows; then hold
        yield from press(panel, button)
    hand[:] = [wave(time.monotonic())]
    yield 8.0
    window.grab().save(os.path.join(out_dir, 'gui_main.png'))
    window.tabs.setCurrentWidget(tab)
    yield 4.0
    window.grab().save(os.path.join(out_dir, 'gui_joint%d.png' % WAVED_JOINT))
    hand[:] = []
    if client.state.snapshot().opmode == interface.HOLD:
        yield from press(panel, 1)  # limp again: the hand alone moves the puppet
    hand[:] = [reach(time.monotonic(), panel.angles())]
    yield REACH_S
    give_up_s = time.monotonic() + STEP_TIMEOUT_S
    while not baxter.near(REACH_POSE_RAD, REACHED_RAD):
        if time.monotonic() > give_up_s:
            raise GaveUp("Baxter's right arm did not reach %s: %s" % (
                REACH_POSE_RAD, baxter.positions()))
        teleop = client.state.snapshot().teleop
        if teleop is not None and teleop.state == interface.READY:
            yield from press(panel, 3)  # following stopped (a fault on a busy machine): again
        yield 0.5
    pane = window.camera_pane
    window.tabs.setCurrentWidget(window.main_tab)   # the camera pane sits beside the status
    pane.choose(CAMERA)
    yield 3.0  # a full window of frames/s (camera_view.RATE_WINDOW_S) once it streams
    yield lambda: (pane.view.has_image() and pane.verdict().level == camera_view.OK
                   and pane.client.slot.rate_hz(pane.client.now(), pane.client.subscribed_s)
                   >= CAMERA_RATE_HZ)
    window.grab().scaledToWidth(CAMERA_SHOT_WIDTH, QtCore.Qt.SmoothTransformation).save(
        os.path.join(out_dir, 'gui_camera_reach.jpg'), 'JPG', JPEG_QUALITY)


def press(panel, button):
    """Press and release one of the panel's buttons 1-4 (yields the waits)."""
    panel.user_buttons[button - 1].pressed.emit()
    yield 0.4
    panel.user_buttons[button - 1].released.emit()
    yield 1.0


def wave(start_s):
    """Return a hand that waves WAVED_JOINT against the hold controller from start_s on."""
    def move(panel, now_s):
        panel.set_angle(WAVED_JOINT, 0.5 + 0.4 * math.sin(1.5 * (now_s - start_s)))
    return move


def reach(start_s, from_rad):
    """Return a hand that moves every joint from from_rad to REACH_POSE_RAD in REACH_S."""
    def move(panel, now_s):
        part = min((now_s - start_s) / REACH_S, 1.0)
        for joint, (a, b) in enumerate(zip(from_rad, REACH_POSE_RAD)):
            panel.set_angle(joint, a + part * (b - a))
    return move


def run(name, scenario, debug_mode):
    """Build gui_R's window (debug_mode: its joint tabs) and run scenario(window, out_dir, hand,
    baxter) step by step (it yields seconds to wait or a predicate to wait for); return the
    output folder (argv[1]), or exit with status 1 when a step does not happen in time."""
    out_dir = sys.argv[1]
    rospy.init_node('gui_R')
    app = QtWidgets.QApplication([name])
    window = Window(PuppetClient('R', ArmState()), debug_mode, SimPuppetClient('R'),
                    CameraClient())
    window.show()
    hand = []  # what moves the panel's sliders each tick
    steps = scenario(window, out_dir, hand, BaxterRightArm())
    wait = [0.0, time.monotonic()]  # what to wait for, since when
    failure = []

    def tick():
        window.frame()
        for move in hand:
            move(window.sim_panel, time.monotonic())
        what, since = wait
        done = what() if callable(what) else time.monotonic() - since >= what
        try:
            if done:
                wait[:] = [next(steps), time.monotonic()]
            elif time.monotonic() - since > STEP_TIMEOUT_S:
                snap = window.client.state.snapshot()
                raise GaveUp('waited %.0f s (encoders: %s; teleop: %s)' % (
                    STEP_TIMEOUT_S, [j.status for j in snap.joints], snap.teleop))
        except StopIteration:
            app.quit()
        except GaveUp as reason:
            failure.append(str(reason))
            app.quit()

    timer = QtCore.QTimer()
    timer.timeout.connect(tick)
    timer.start(33)
    app.exec_()
    rospy.signal_shutdown('screenshots taken' if not failure else 'gave up')
    if failure:
        sys.exit('%s: gave up: %s' % (name, failure[0]))
    return out_dir


def main():
    out_dir = run('screenshot_gui', scenario, True)
    print('screenshots in %s: gui_main.png, gui_joint%d.png, gui_camera_reach.jpg'
          % (out_dir, WAVED_JOINT))


if __name__ == '__main__':
    main()
