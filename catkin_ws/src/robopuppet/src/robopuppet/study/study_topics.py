"""The study node's ROS side: what it watches, its StudyState message, the recorder's service,
the tasks' API loaded when the node starts."""
import threading

import rospy
from baxter_core_msgs.msg import EndEffectorState
from geometry_msgs.msg import Point, Pose, Quaternion
from sensor_msgs.msg import JointState
from visualization_msgs.msg import Marker, MarkerArray

from robopuppet import interface as ifc
from robopuppet.assist.dataset import CLOSED_BELOW_PERCENT
from robopuppet.study import study_run
from robopuppet_msgs.msg import StudyState, TeleopState
from robopuppet_msgs.srv import Record, RecordRequest

READY_STATES = (ifc.READY, ifc.FOLLOWING)
STATE_EVERY_S = 0.5    # StudyState at least this often (every step in a trial)
MARKERS_EVERY = 4      # the task markers every 4th publication in a trial
RECORDER_WAIT_S = 0.5   # how long a trial's start waits for the recorder's service to appear


def task_api():
    """Return the tasks' TaskApi (study.tasks, task_judge, metrics), task_markers, tips_of
    (imported when the node starts, so that a --help need not load the tasks' kinematics)."""
    from robopuppet.study import metrics, task_judge, task_markers, tasks  # noqa: E501
    return (study_run.TaskApi(tasks.make_trial, task_judge.TrialJudge, metrics.TrialMetrics,
                              tasks.TIMEOUT_S), task_markers.task_markers, task_judge.tips_of)


class StudyWatch:
    """The latest teleop_state of each puppet side, Baxter's joint_states and grippers.

    Subscribes: /puppet/arm_X/teleop_state (X: L, R), /robot/joint_states,
    /robot/end_effector/<arm>_gripper/state."""

    def __init__(self, tips_of):
        self._tips_of, self._lock = tips_of, threading.Lock()
        self._teleop, self._joints, self._closed = {}, None, dict.fromkeys(ifc.BAXTER_SIDES, False)
        for side in ifc.PUPPET_SIDES:
            rospy.Subscriber(ifc.puppet_ns(side) + '/' + ifc.TELEOP_STATE, TeleopState,
                             self._keep, ('teleop', side), queue_size=4)
        rospy.Subscriber(ifc.ROBOT_JOINT_STATES, JointState, self._keep, ('joints', None),
                         queue_size=1)
        for arm in ifc.BAXTER_SIDES:
            rospy.Subscriber(ifc.baxter_gripper_topic(arm, 'state'), EndEffectorState,
                             self._keep, ('gripper', arm), queue_size=1)

    def _keep(self, msg, key):
        kind, which = key
        with self._lock:
            if kind == 'teleop':
                self._teleop[which] = msg
            elif kind == 'joints':
                self._joints = msg
            else:
                self._closed[which] = msg.position < CLOSED_BELOW_PERCENT

    def seen(self):
        """Return what the runner needs now (study_run.Seen); tips None before Baxter's first
        joint_states or when they lack an arm's joints."""
        with self._lock:
            teleop, joints, closed = dict(self._teleop), self._joints, dict(self._closed)
        tips = None
        if joints is not None:
            try:
                tips = self._tips_of(joints.name, joints.position)
            except (KeyError, ValueError):
                tips = None
        states = list(teleop.values())
        following = {arm: any(getattr(s, 'follow_' + arm) for s in states)
                     for arm in ifc.BAXTER_SIDES}
        held = {arm: any(getattr(s, 'zone_' + arm) for s in states) for arm in ifc.BAXTER_SIDES}
        ready = {side: s.state in READY_STATES for side, s in teleop.items()}
        return study_run.Seen(ready, tips, closed, following, held)


def state_msg(state, results_path, stamp):
    """Return the StudyState message of a study_run.State."""
    msg = StudyState(phase=state.phase, participant=state.participant, device=state.device,
                     task=state.task, practice=state.practice, trial=state.trial,
                     trials=state.trials, seed=state.seed, elapsed=state.elapsed,
                     results=results_path, detail=state.detail)
    msg.header.stamp = stamp
    for goal in state.goals:
        quat = goal.quat if goal.quat is not None else (0.0, 0.0, 0.0, 1.0)
        msg.targets.append(Pose(Point(*goal.xyz), Quaternion(*quat)))
        msg.target_arms.append(goal.arm)
        msg.target_closed.append(bool(goal.closed))
        msg.target_tolerance.append(goal.tolerance_m)
    return msg


class RecordClient:
    """The recorder's Record service (interface.RECORD_SERVICE); a trial without a recorder
    is not recorded (one warning)."""

    def __init__(self, name):
        self._name, self._proxy, self._warned = name, None, False

    def call(self, start, task=''):
        """Start (task text) or stop an episode. Returns the episode file, '' when none."""
        try:
            if self._proxy is None:
                rospy.wait_for_service(ifc.RECORD_SERVICE, RECORDER_WAIT_S)
                self._proxy = rospy.ServiceProxy(ifc.RECORD_SERVICE, Record)
            answer = self._proxy(RecordRequest(start=start, task=task))
        except (rospy.ROSException, rospy.ServiceException) as error:
            self._proxy = None
            if start and not self._warned:
                self._warned = True
                rospy.logwarn('%s: trials are not recorded: no recorder (%s)', self._name, error)
            return ''
        if not answer.ok:
            rospy.logwarn('%s: the recorder refused to %s: %s', self._name,
                          'start' if start else 'stop', answer.error)
        return answer.episode if answer.ok else ''


class StudyPublishers:
    """StudyState (latched; every call in a trial, else on change and every STATE_EVERY_S) and
    the task markers (latched; cleared outside a trial). Args: markers (task_markers), the
    trials' CSV path."""

    def __init__(self, markers, results_path):
        self._markers, self._results = markers, results_path
        self._state = rospy.Publisher(ifc.STUDY_STATE, StudyState, queue_size=2, latch=True)
        self._marker = rospy.Publisher(ifc.STUDY_MARKERS, MarkerArray, queue_size=2, latch=True)
        self._last, self._shown, self._count, self._judge = None, 0.0, 0, None

    def publish(self, now, state, judge):
        """Publish what is due; return whether the state changed (more than its elapsed)."""
        key = state._replace(elapsed=0.0, goals=len(state.goals))
        changed = key != self._last
        stamp = rospy.Time.now()
        if state.phase == study_run.TRIAL or changed or now - self._shown >= STATE_EVERY_S:
            self._state.publish(state_msg(state, self._results, stamp))
            self._last, self._shown = key, now
        self._count += 1
        if (judge is not None and self._count % MARKERS_EVERY == 0) or judge is not self._judge:
            self._marker.publish(self._markers(judge, stamp) if judge is not None else
                                 MarkerArray([Marker(action=Marker.DELETEALL)]))
        self._judge = judge
        return changed
