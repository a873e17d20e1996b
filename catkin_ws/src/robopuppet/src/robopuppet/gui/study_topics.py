"""The study tab's ROS client: the study runner's state, its Start/Stop service and the
questionnaire's answers (robopuppet.study; docs/study.md).

No Qt here: the state callback runs on rospy's thread and only sets the locked latest state; the
GUI thread reads it once per frame (gui.study_tab). The service call blocks, so the tab makes it
off its thread (gui.config_task).
"""
import collections
import threading

import rospy

from robopuppet import interface
from robopuppet.gui.puppet_client import ConfigUnavailable
from robopuppet_msgs.msg import Questionnaire, StudyState
from robopuppet_msgs.srv import StudyStart

# A robopuppet_msgs/StudyState's fields as the tab shows them; goals: (arm, (x, y, z) m, closed,
# tolerance m) per target; received_s: the GUI's own receive time (s).
Study = collections.namedtuple('Study', 'phase participant device task practice trial trials '
                                        'seed goals elapsed_s results detail received_s')
StartAnswer = collections.namedtuple('StartAnswer', 'ok error results')
StartAnswer.__doc__ = """The runner's answer to StudyStart: ok (bool), error (why not, or ''),
results (the trials' CSV file the study writes)."""


def study_of(msg, received_s):
    """Return the Study of a robopuppet_msgs/StudyState received at received_s (s)."""
    goals = tuple((arm, (pose.position.x, pose.position.y, pose.position.z), bool(closed),
                   float(tolerance))
                  for arm, pose, closed, tolerance in zip(
                      msg.target_arms, msg.targets, msg.target_closed, msg.target_tolerance))
    return Study(msg.phase, msg.participant, msg.device, msg.task, msg.practice, msg.trial,
                 msg.trials, msg.seed, goals, msg.elapsed, msg.results, msg.detail, received_s)


class StudyTopics:
    """Keep the study runner's latest state; start and stop a study; send the questionnaire.

    Subscribes interface.STUDY_STATE (robopuppet_msgs/StudyState, latched; queue 1).
    Publishes interface.STUDY_QUESTIONNAIRE (robopuppet_msgs/Questionnaire).
    Calls interface.STUDY_START (robopuppet_msgs/StudyStart).

    Args:
        clock: returns the time (s) a message is received at.
    """

    def __init__(self, clock=rospy.get_time):
        self._clock = clock
        self._lock = threading.Lock()
        self._study = None
        self._start = rospy.ServiceProxy(interface.STUDY_START, StudyStart)
        self._answers_pub = rospy.Publisher(interface.STUDY_QUESTIONNAIRE, Questionnaire,
                                            queue_size=4)
        self._subscriber = rospy.Subscriber(interface.STUDY_STATE, StudyState, self._on_state,
                                            queue_size=1)

    def now(self):
        """Return the current ROS time in s (the time base of received_s)."""
        return self._clock()

    def study_state(self):
        """Return the runner's latest Study, or None before the first."""
        with self._lock:
            return self._study

    def start_study(self, start, participant='', timeout_s=1.0):
        """Ask the runner to start a study for participant (start True; its ~devices and
        ~tasks) or to stop the running one; return a StartAnswer. Blocks: call it off the GUI
        thread.

        Raises:
            ConfigUnavailable: the runner's service is not there within timeout_s, or the call
                failed.
        """
        try:
            self._start.wait_for_service(timeout_s)
            response = self._start(start, participant, [], [])
        except (rospy.ROSException, rospy.ServiceException) as error:
            raise ConfigUnavailable('%s: %s' % (interface.STUDY_START, error)) from None
        return StartAnswer(response.ok, response.error, response.results)

    def send_questionnaire(self, participant, device, tlx, sus):
        """Publish one participant's answers about one device (6 TLX ratings, 10 SUS answers)."""
        msg = Questionnaire(participant=participant, device=device,
                            tlx=[float(r) for r in tlx], sus=[int(a) for a in sus])
        msg.header.stamp = rospy.Time.from_sec(self._clock())
        self._answers_pub.publish(msg)

    def _on_state(self, msg):
        study = study_of(msg, self._clock())
        with self._lock:
            self._study = study
