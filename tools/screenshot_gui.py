#!/usr/bin/python3
"""Drive the real GUI against the running simulated arm R and save two screenshots.

Usage: tools/screenshot_gui.py OUT_DIR   (started by tools/screenshot_gui.sh, which also starts
the simulated system). Builds the same window as gui_R (PuppetClient + virtual puppet panel),
then, like an operator: sweeps the quadrature joints through their index marks with the panel's
sliders until all seven encoders work, makes joint 1 a P controller (pid_kp 4 V/rad, no I or
D) with the joint tab's Set, presses button 3 (Baxter's right arm follows) and button 1 (hold),
and waves joint 1 with its slider. Saves OUT_DIR/gui_main.png (main tab) and
OUT_DIR/gui_joint1.png (joint 1 tab). Exits with status 1, saving nothing more, when a step
does not happen within a minute or Set is not confirmed.
"""
import math
import os
import sys
import time

import rospy
from PyQt5 import QtCore, QtWidgets

from robopuppet import interface
from robopuppet.gui.puppet_client import PuppetClient, SimPuppetClient
from robopuppet.gui.state import ArmState
from robopuppet.gui.window import Window

WAVED_JOINT = 1
STEP_TIMEOUT_S = 60.0


class GaveUp(Exception):
    """The scenario cannot go on; str() says why."""


def scenario(window, out_dir, wave):
    """Yield seconds to wait (or a predicate to wait for) between the operator's actions."""
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
        panel.user_buttons[button - 1].pressed.emit()
        yield 0.4
        panel.user_buttons[button - 1].released.emit()
        yield 1.0
    wave.append(time.monotonic())
    yield 8.0
    window.grab().save(os.path.join(out_dir, 'gui_main.png'))
    window.tabs.setCurrentWidget(tab)
    yield 4.0
    window.grab().save(os.path.join(out_dir, 'gui_joint%d.png' % WAVED_JOINT))


def main():
    out_dir = sys.argv[1]
    rospy.init_node('gui_R')
    app = QtWidgets.QApplication(['screenshot_gui'])
    window = Window(PuppetClient('R', ArmState()), True, SimPuppetClient('R'))
    window.show()
    wave = []  # when the waving of WAVED_JOINT started
    steps = scenario(window, out_dir, wave)
    wait = [0.0, time.monotonic()]  # what to wait for, since when
    failure = []

    def tick():
        window.frame()
        if wave:  # the hand waves the joint against the hold controller
            phase = 1.5 * (time.monotonic() - wave[0])
            window.sim_panel.set_angle(WAVED_JOINT, 0.5 + 0.4 * math.sin(phase))
        what, since = wait
        done = what() if callable(what) else time.monotonic() - since >= what
        try:
            if done:
                wait[:] = [next(steps), time.monotonic()]
            elif time.monotonic() - since > STEP_TIMEOUT_S:
                raise GaveUp('waited %.0f s (encoders: %s)' % (STEP_TIMEOUT_S, [
                    j.status for j in window.client.state.snapshot().joints]))
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
        sys.exit('screenshot_gui: gave up: %s' % failure[0])
    print('screenshots in %s: gui_main.png, gui_joint%d.png' % (out_dir, WAVED_JOINT))


if __name__ == '__main__':
    main()
