#!/usr/bin/python3
"""Screenshot the GUI's study tab during a trial and its questionnaire.

Usage: tools/screenshot_study.py [--ros] [OUT_DIR]   (default ./screenshots; runs on Qt's
offscreen platform unless $DISPLAY is set). Builds gui_R's real window with its study tab.
Without --ros it is fed, with no ROS at all, the robopuppet_msgs/StudyState a study runner
publishes in trial 7 of 24 (pick_place with the keyboard, one goal) and then in its questionnaire
phase, through the same conversion as the GUI's ROS client (gui.study_topics.study_of).
With --ros it runs against a running `roslaunch robopuppet study.launch gui:=false ...` as gui_R
(PuppetClient, StudyTopics): enters participant P01, clicks Start, waits for a trial with goals
running for over 3 s, then for the questionnaire (a trial nobody drives ends at its timeout).
Saves OUT_DIR/study_tab.png (the window on the study tab) and OUT_DIR/study_questionnaire.png
(the dialog, partly answered, after a Submit that refuses the unanswered statement); with --ros
it then answers in full and waits until the runner moves on. Exits 1 when a step times out.
"""
import os
import sys
import time

if not os.environ.get('DISPLAY'):
    os.environ.setdefault('QT_QPA_PLATFORM', 'offscreen')

from geometry_msgs.msg import Point, Pose  # noqa: E402
from PyQt5 import QtWidgets  # noqa: E402

from robopuppet.gui.state import ArmState  # noqa: E402
from robopuppet.gui.study_topics import StartAnswer, study_of  # noqa: E402
from robopuppet.gui.window import Window  # noqa: E402
from robopuppet_msgs.msg import StudyState  # noqa: E402

RESULTS = '/home/lab/.ros/robopuppet/studies/pilot/trials.csv'
NOW_S = 1000.0


class StandIn:
    """What the window asks of gui_R's clients: one arm with nothing heard, a study runner."""

    side = 'R'

    def __init__(self):
        self.state = ArmState()
        self.study = None
        self.sent = []

    def now(self):
        return NOW_S

    def recording_status(self):
        return None

    def episodes_dir(self):
        return '/nonexistent'

    def study_state(self):
        return self.study

    def start_study(self, start, participant=''):
        return StartAnswer(True, '', RESULTS)

    def send_questionnaire(self, participant, device, tlx, sus):
        self.sent.append((participant, device, tlx, sus))


def trial_state(phase):
    """Return a StudyState of participant P03's trial 7 of 24 in `phase`."""
    msg = StudyState(phase=phase, participant='P03', device='keyboard', task='pick_place',
                     trial=7, trials=24, seed=4107, elapsed=14.2, results=RESULTS)
    if phase == StudyState.TRIAL:
        msg.targets = [Pose(position=Point(0.74, -0.41, -0.06))]
        msg.target_arms, msg.target_closed, msg.target_tolerance = ['right'], [True], [0.04]
        msg.detail = ('trial 7 of 24: the object is in the gripper; release it within 4 cm of '
                      'spot B')
    else:
        msg.detail = 'answer the questionnaire about keyboard'
    return msg


TLX = (55, 30, 45, 20, 60, 35)
SUS = (4, 2, 4, 1, 4, 2, 5, 2, None, 2)   # statement 9 unanswered: Submit refuses
STEP_TIMEOUT_S = 600.0


def fill(dialog, sus):
    """Move the sliders to TLX and click the SUS answers (None: leave unanswered)."""
    for slider, rating in zip(dialog.sliders, TLX):
        slider.setValue(rating // 5)
    for group, answer in zip(dialog.answer_groups, sus):
        if answer is not None:
            group.button(answer).click()


def wait_until(app, window, predicate, what):
    """Draw frames until predicate() holds; exit 1 after STEP_TIMEOUT_S."""
    give_up_s = time.monotonic() + STEP_TIMEOUT_S
    while not predicate():
        if time.monotonic() > give_up_s:
            sys.exit('screenshot_study: gave up waiting for %s' % what)
        window.frame()
        app.processEvents()
        time.sleep(1 / 30.0)
    window.frame()   # show what the predicate saw
    app.processEvents()


def live(out_dir):
    """Run against a running study.launch (see the module's docstring)."""
    import rospy
    from robopuppet.gui.puppet_client import PuppetClient, SimPuppetClient
    from robopuppet.gui.study_topics import StudyTopics
    rospy.init_node('gui_R')
    app = QtWidgets.QApplication(sys.argv[:1])
    study = StudyTopics()
    window = Window(PuppetClient('R', ArmState()), False, SimPuppetClient('R'), None, study)
    window.show()
    tab = window.study_tab
    wait_until(app, window, lambda: study.study_state() is not None, 'the runner')
    tab.participant.setText('P01')
    tab.start_button.click()
    wait_until(app, window, lambda: (study.study_state().phase == StudyState.TRIAL
                                     and study.study_state().goals
                                     and study.study_state().elapsed_s > 3.0), 'a trial')
    window.grab().save(os.path.join(out_dir, 'study_tab.png'))
    wait_until(app, window, lambda: tab.dialog is not None, 'the questionnaire')
    fill(tab.dialog, SUS)
    tab.dialog.submit_button.click()
    app.processEvents()
    tab.dialog.grab().save(os.path.join(out_dir, 'study_questionnaire.png'))
    device = tab.dialog.device
    fill(tab.dialog, SUS[:8] + (3,) + SUS[9:])
    tab.dialog.submit_button.click()
    wait_until(app, window, lambda: (study.study_state().phase != StudyState.QUESTIONNAIRE
                                     or study.study_state().device != device),
               'the runner to take the answers')
    print('saved the screenshots in %s; the runner is in phase %s: %s' % (
        out_dir, study.study_state().phase, study.study_state().detail))
    rospy.signal_shutdown('screenshots taken')
    return 0


def main():
    args = [a for a in sys.argv[1:] if a != '--ros']
    out_dir = os.path.abspath(args[0] if args else 'screenshots')
    os.makedirs(out_dir, exist_ok=True)
    if '--ros' in sys.argv[1:]:
        return live(out_dir)
    app = QtWidgets.QApplication(sys.argv[:1])
    stand_in = StandIn()
    window = Window(stand_in, debug_mode=False, study=stand_in)
    window.show()
    tab = window.study_tab
    tab.participant.setText('P03')
    stand_in.study = study_of(trial_state(StudyState.TRIAL), NOW_S - 0.05)
    window.frame()
    app.processEvents()
    window.grab().save(os.path.join(out_dir, 'study_tab.png'))
    stand_in.study = study_of(trial_state(StudyState.QUESTIONNAIRE), NOW_S - 0.05)
    window.frame()
    dialog = tab.dialog
    fill(dialog, SUS)
    dialog.submit_button.click()   # statement 9 is not answered: refused, said in red
    app.processEvents()
    dialog.grab().save(os.path.join(out_dir, 'study_questionnaire.png'))
    print('saved %s and %s' % (os.path.join(out_dir, 'study_tab.png'),
                               os.path.join(out_dir, 'study_questionnaire.png')))
    return 0 if not stand_in.sent else 1


if __name__ == '__main__':
    sys.exit(main())
