#!/usr/bin/python3
"""Drive the real GUI into feel mode against a keep-out zone and save the main tab.

Usage: tools/screenshot_gui_feel.py OUT_DIR   (started by `tools/screenshot_gui.sh --feel`,
which also starts the simulated system with config/zones.yaml). Builds the same window as gui_R,
then, like an operator: sweeps the quadrature joints through their index marks, presses button 3
(Baxter's right arm follows), moves the sliders to screenshot_gui.REACH_POSE_RAD (the hand out
over the bed) and waits for Baxter to be there, clicks the opmode control's `feel`, and lowers
the shoulder (joint 1) toward PUSH_S1_RAD, which would put Baxter's gripper into the "patient
body" zone: arm_X holds Baxter at the zone's edge and the puppet, in feel, pulls back. Saves
OUT_DIR/gui_feel.jpg once the main tab names the zone and feel is still on. Exits with status
1 when a step does not happen within a minute.
"""
import os
import time

from PyQt5 import QtCore

import screenshot_gui
from robopuppet import interface
from screenshot_gui import (JPEG_QUALITY, REACH_POSE_RAD, REACH_S, STEP_TIMEOUT_S, GaveUp, press,
                            reach)

# Joint 1 (s1) of REACH_POSE_RAD lowered to this puts the gripper 5 cm deep into "patient body"
# (baxter_description's FK: x 0.60 m, z -0.06 m; the zone's top is at z -0.025 m).
PUSH_S1_RAD = -0.5
PUSH_S = 3.0
SHOT_WIDTH = 1024  # pixels
ATTEMPTS = 3


def scenario(window, out_dir, hand, baxter):
    """Yield seconds to wait (or a predicate to wait for) between the operator's actions."""
    panel, client, tab = window.sim_panel, window.client, window.main_tab
    snapshot = client.state.snapshot
    yield lambda: snapshot().heartbeat_s is not None and window.sim.connected()
    for joint in (0, 2, 4, 6):  # quadrature encoders calibrate at their index mark (0 rad)
        for angle in (-0.6, 0.6, 0.2):
            panel.set_angle(joint, angle)
            yield 0.7
    yield lambda: all(j.status == interface.WORKING for j in snapshot().joints)
    yield from press(panel, 3)
    hand[:] = [reach(time.monotonic(), panel.angles())]
    yield REACH_S
    give_up_s = time.monotonic() + STEP_TIMEOUT_S
    while not baxter.near(REACH_POSE_RAD, 0.03):
        if time.monotonic() > give_up_s:
            raise GaveUp("Baxter's right arm did not reach %s: %s" % (
                REACH_POSE_RAD, baxter.positions()))
        if snapshot().teleop is not None and snapshot().teleop.state == interface.READY:
            yield from press(panel, 3)  # following stopped (a fault on a busy machine): again
        yield 0.5
    hand[:] = [push(time.monotonic(), panel.angles())]
    for _ in range(ATTEMPTS):  # a busy machine's puppet timeout ends following and feel: again
        if snapshot().teleop.state == interface.READY:
            yield from press(panel, 3)
        if snapshot().opmode != interface.FEEL:
            tab.feel_radio.click()
        yield PUSH_S + 1.5  # the push is done and the error columns settle
        if 'keep-out zone' in tab.tracking_label.text() and snapshot().opmode == interface.FEEL:
            break
    else:
        raise GaveUp('no zone in feel mode after %d attempts: %s' % (ATTEMPTS, snapshot().teleop))
    window.grab().scaledToWidth(SHOT_WIDTH, QtCore.Qt.SmoothTransformation).save(
        os.path.join(out_dir, 'gui_feel.jpg'), 'JPG', JPEG_QUALITY)
    print('tracking line: %s' % tab.tracking_label.text())


def push(start_s, from_rad):
    """Return a hand that lowers joint 1 from where it is to PUSH_S1_RAD in PUSH_S."""
    def move(panel, now_s):
        part = min((now_s - start_s) / PUSH_S, 1.0)
        panel.set_angle(1, from_rad[1] + part * (PUSH_S1_RAD - from_rad[1]))
    return move


def main():
    out_dir = screenshot_gui.run('screenshot_gui_feel', scenario, False)
    print('screenshot in %s: gui_feel.jpg' % out_dir)


if __name__ == '__main__':
    main()
