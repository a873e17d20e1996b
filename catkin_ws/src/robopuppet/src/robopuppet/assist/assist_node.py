"""assist: one Baxter arm's target predicted from the other's motion (assist_core decides)."""
import os
import threading
import time

import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import String

from robopuppet import interface as ifc, params
from robopuppet.assist import assist_core, model_file
from robopuppet.assist.assist_core import PUPPET_OF
from robopuppet.baxter_description import arm_joint_names
from robopuppet.periodic import Guard, Loop
from robopuppet_msgs.msg import AssistState, AssistTarget, TeleopState

MODEL_CHECK_S = 1.0   # how often a missing or broken model file is looked at again
WARN_EVERY_S = 5.0    # the same kind of garbage is logged at most this often


class AssistNode:
    """Load the model, step it with the leader arm's measured pose, publish its target, which
    the leading puppet's arm_X carries out through its own safety path (docs/assist.md).

    ROS API (<leader>, <follower>: puppet_ns of the model's leader and follower arm's side):
      Subscribes: /robot/joint_states, /puppet/assist_command (String 'stop' or 'start'),
        <leader>/teleop_state (assist_<follower arm>).
      Publishes: <leader>/assist_target (AssistTarget, each step), /puppet/assist_state
        (AssistState, latched), for the ghost (25 Hz, JointState) <follower>/assist_prediction
        (the prediction) and <leader>/assist_prediction (the leader's measured pose).
      Parameters: ~model (str, the model file), ~rate (Hz, 100), ~leader_timeout (s, 0.2)."""

    def __init__(self):
        self._name = rospy.get_name()
        self._path = os.path.expanduser(str(rospy.get_param('~model', '')))
        rate_hz = params.positive('~rate', rospy.get_param('~rate', 100.0))
        timeout_s = params.positive('~leader_timeout', rospy.get_param(
            '~leader_timeout', assist_core.LEADER_TIMEOUT_S))
        self._waiting = ('waiting for the model file %s: record demonstrations and run '
                         'train_assist (docs/assist.md)' % self._path)
        self._core = assist_core.AssistCore(None, rate_hz, timeout_s, problem=self._waiting)
        self._lock, self._guard = threading.Lock(), Guard(self._name, rospy.logerr)
        # the model problem said last, the (mtime, size) of the model file tried, the stamp
        # of the leader pose in use, the (state, detail) logged last; the arms' publishers
        self._said, self._tried, self._stamp, self._shown, self._pubs = None, None, None, None, {}
        self._state_pub = rospy.Publisher(ifc.ASSIST_STATE, AssistState, queue_size=1, latch=True)
        rospy.Subscriber(ifc.ROBOT_JOINT_STATES, JointState, self._take, self._on_robot,
                         queue_size=1)
        rospy.Subscriber(ifc.ASSIST_COMMAND, String, self._take, self._on_command, queue_size=10)
        self._model_loop = Loop(self._guard, 'loader', MODEL_CHECK_S, self._check_model).start()
        self._loop = Loop(self._guard, 'assist loop', 1.0 / rate_hz, self._step).start()
        rospy.on_shutdown(lambda: (self._model_loop.stop(), self._loop.stop()))

    def _take(self, msg, handler):
        """Run a subscriber callback under the lock and the guard; log what it warns of."""
        with self._lock:
            problem = self._guard.call(handler.__name__, handler, msg)
        if problem:
            rospy.logwarn_throttle(WARN_EVERY_S, '%s: %s', self._name, problem)

    def _check_model(self):
        """Load the model file once it is there (and again after a failure, when it changed)."""
        try:
            stat = os.stat(self._path)
        except OSError:
            return self._problem(self._waiting, rospy.loginfo)
        if (stat.st_mtime, stat.st_size) == self._tried:
            return None
        self._tried = (stat.st_mtime, stat.st_size)
        try:
            predictor = model_file.load(self._path)
        except (model_file.ModelError, OSError) as error:
            return self._problem('cannot use the model: %s' % error, rospy.logerr)
        with self._lock:
            problem = self._core.on_model(time.monotonic(), predictor)
            if not problem:
                self._connect(predictor)
                self._model_loop.stop()
        if problem:
            return self._problem(problem, rospy.logerr)
        return rospy.loginfo('%s: loaded %s (task %r, method %s)', self._name, self._path,
                             predictor.task, predictor.method)

    def _problem(self, text, log):
        """Say a model problem once and turn the assist off with it."""
        if text != self._said:
            self._said = text
            log('%s: %s' % (self._name, text))
            with self._lock:
                self._core.on_model(time.monotonic(), None, text)

    def _connect(self, predictor):
        """Make the publishers and the teleop_state subscription of the model's arms."""
        leader, follower = (ifc.puppet_ns(PUPPET_OF[s]) + '/'
                            for s in (predictor.leader, predictor.follower))
        self._pubs = {key: rospy.Publisher(ns + topic, kind, queue_size=1) for key, ns, topic, kind
                      in (('target', leader, ifc.ASSIST_TARGET, AssistTarget),
                          ('ghost', follower, ifc.ASSIST_PREDICTION, JointState),
                          ('leader', leader, ifc.ASSIST_PREDICTION, JointState))}
        rospy.Subscriber(leader + ifc.TELEOP_STATE, TeleopState, self._take, self._on_teleop,
                         queue_size=10)

    def _on_robot(self, msg):
        if self._core.predictor is None:
            return ''
        try:
            problem = self._core.on_leader_pose(time.monotonic(), assist_core.arm_positions(
                msg.name, msg.position, self._core.predictor.leader))
        except ValueError as error:
            return '/robot/joint_states ignored: %s' % error
        if not problem:  # a stamp of 0: the time it came
            self._stamp = rospy.Time.now() if msg.header.stamp.is_zero() else msg.header.stamp
        return problem

    def _on_command(self, msg):
        problem = self._core.on_command(time.monotonic(), msg.data)
        if problem:  # each one said: a person's command, not a stream
            rospy.logwarn('%s: %s', self._name, problem)

    def _on_teleop(self, msg):
        follower = self._core.predictor.follower
        self._core.on_teleop_state(time.monotonic(), getattr(msg, 'assist_' + follower))

    def _step(self):
        with self._lock:
            step, stamp, pubs = self._core.step(time.monotonic()), self._stamp, self._pubs
        if step.warning:
            rospy.logwarn_throttle(WARN_EVERY_S, '%s: %s', self._name, step.warning)
        now = rospy.Time.now()
        if step.target is not None and pubs:
            pubs['target'].publish(AssistTarget(
                rospy.Header(stamp=now if stamp is None else stamp), *step.target))
        if step.ghost is not None and pubs:
            for key, arm, pose in (('ghost', step.state.follower, step.ghost),
                                   ('leader', step.state.leader, step.leader_pose)):
                pubs[key].publish(JointState(header=rospy.Header(stamp=now),
                                             name=arm_joint_names(arm), position=pose))
        if step.publish_state:
            self._state_pub.publish(AssistState(rospy.Header(stamp=now), *step.state))
        if step.state[::6] != self._shown:  # off: said by _problem
            self._shown = step.state[::6]
            if step.state.state != assist_core.OFF:
                rospy.loginfo('%s: %s', self._name, step.state.detail)


def main():
    """Run the assist node until shutdown."""
    rospy.init_node('assist')
    AssistNode()
    rospy.spin()
