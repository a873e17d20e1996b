"""sim_participant: the simulated participant of a user study (study.participant, docs/study.md).

Watches the study runner's state; while a trial runs, drives the trial's device toward its goals
as a person would (study.participant), through study.participant_outputs; before a trial,
calibrates a new simulated puppet and lets go of the arms; in the questionnaire, answers for the
device (participant.answers, seeded).
"""
import threading

import numpy as np
import rospkg
import rospy
from sensor_msgs.msg import JointState

from robopuppet import baxter_description as bd, interface, params
from robopuppet.study import participant, participant_answers, participant_hands, tasks
from robopuppet.study.participant_outputs import Outputs
from robopuppet_msgs.msg import Questionnaire, StudyState, TeleopState

PUPPET_SIDE = {'left': 'L', 'right': 'R'}


class ParticipantNode:
    """The simulated participant's ROS side.

    Subscribes interface.STUDY_STATE, /robot/joint_states, puppet_ns(X)/teleop_state (X: L, R);
    publishes interface.STUDY_QUESTIONNAIRE (latched), and participant_outputs' topics.
    Parameters: ~events ({device: FIFO path prefix}, the study node's; FIFOs <prefix>_L and
    _R are made), ~seed (int, 0: with each trial's seed, the noise's), ~rate (Hz, 50),
    ~jog_speed (rad/s, 0.4), ~max_speed (m/s, 0.15), ~max_turn (rad/s, 0.6): the devices'.
    """

    def __init__(self):
        self._seed = int(rospy.get_param('~seed', 0))
        self._speeds = {name: params.positive('~' + name, rospy.get_param('~' + name, default))
                        for name, default in participant_hands.SPEEDS.items()}
        self._rate_hz = params.positive('~rate', rospy.get_param('~rate', 50.0))
        self._description = bd.Description(rospy.get_param(
            interface.ROBOT_DESCRIPTION_PARAM, None) or bd.read_urdf(
                bd.urdf_path(rospkg.RosPack().get_path('robopuppet'))))
        self._outputs = Outputs(rospy.get_param('~events', {}))
        self._lock = threading.Lock()
        self._state, self._angles, self._teleop = None, {}, {}
        self._person, self._person_key, self._trial = None, None, None
        self._answered, self._driving = set(), False
        self._answers = rospy.Publisher(interface.STUDY_QUESTIONNAIRE, Questionnaire,
                                        queue_size=10, latch=True)
        rospy.Subscriber(interface.STUDY_STATE, StudyState, self._keep, 'state', queue_size=10)
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self._on_joints, queue_size=1)
        for side in interface.PUPPET_SIDES:
            rospy.Subscriber('%s/%s' % (interface.puppet_ns(side), interface.TELEOP_STATE),
                             TeleopState, self._keep, side, queue_size=10)

    def _keep(self, msg, key):
        with self._lock:
            if key == 'state':
                self._state = msg
            else:
                self._teleop[key] = msg

    def _on_joints(self, msg):
        positions = dict(zip(msg.name, msg.position))
        with self._lock:
            for arm in interface.BAXTER_SIDES:
                names = bd.arm_joint_names(arm)
                if all(n in positions for n in names):
                    self._angles[arm] = np.array([positions[n] for n in names])

    def step(self, t):
        """Act on the study's state at t (s)."""
        with self._lock:
            state, angles, teleop = self._state, dict(self._angles), dict(self._teleop)
        if state is None:
            return
        if state.phase != StudyState.TRIAL:
            if self._driving:
                self._driving = False
                self._outputs.send(t, *self._device, self._person.rest(t))
            if state.phase == StudyState.QUESTIONNAIRE:
                self._answer(state.participant, state.device)
            elif state.phase == StudyState.DEVICE:
                self._between(t, state, angles, teleop)
            return
        arms, sides = self._meet(state.device, state.task)
        if (state.participant, state.trial) != self._trial:
            self._trial = (state.participant, state.trial)
            self._person.begin(t, arms, [self._seed, state.seed])
        self._device, self._driving = (state.device, sides), True
        views = {a: teleop.get(PUPPET_SIDE[a]) for a in arms}
        following = {a: bool(v and getattr(v, 'follow_' + a)) for a, v in views.items()}
        states = {a: v.state for a, v in views.items() if v is not None}
        held = {a: bool(v and getattr(v, 'zone_' + a)) for a, v in views.items()}
        actions = self._person.step(t, participant.targets_of(state), angles, following, states,
                                    held)
        self._outputs.send(t, state.device, sides, actions)

    def _meet(self, device, task):
        """Return a task's arms and puppet sides; the participant of the device and those arms
        is made (and kept while both stay)."""
        arms = tasks.ARMS[task]
        if (device, arms) != self._person_key:
            self._person_key = (device, arms)
            self._person = participant.Participant(device, self._description, self._speeds)
        return arms, tuple(PUPPET_SIDE[a] for a in arms)

    def _between(self, t, state, angles, teleop):
        """Before a trial: a new simulated puppet is calibrated (the runner waits for its arm
        to be ready), and the arms stop following (the runner then brings them to their
        start; the follow press's release comes later, so this runs on)."""
        arms, sides = self._meet(state.device, state.task)
        states = {a: getattr(teleop.get(PUPPET_SIDE[a]), 'state', None) for a in arms}
        following = {a: any(getattr(v, 'follow_' + a) for v in teleop.values())
                     for a in interface.BAXTER_SIDES}
        self._outputs.send(t, state.device, sides, self._person.calibrate(t, arms, angles, states)
                           + self._person.let_go(t, angles, following))

    def _answer(self, who, device):
        """Answer the questionnaire about a device once per participant."""
        if (who, device) in self._answered or device not in participant_answers.TLX_MEAN:
            return
        self._answered.add((who, device))
        tlx, sus = participant_answers.answers(device, self._seed)
        msg = Questionnaire(participant=who, device=device, tlx=tlx, sus=sus)
        msg.header.stamp = rospy.Time.now()
        self._answers.publish(msg)
        rospy.loginfo('sim_participant: answered the questionnaire about %s' % device)

    def spin(self):
        """Step at ~rate until shutdown."""
        rate = rospy.Rate(self._rate_hz)
        try:
            while not rospy.is_shutdown():
                self.step(rospy.get_time())
                rate.sleep()
        except rospy.ROSInterruptException:
            pass
        finally:
            self._outputs.close()


def main():
    """Run the simulated participant node."""
    rospy.init_node('sim_participant')
    ParticipantNode().spin()
