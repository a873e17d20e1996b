"""What serial_X publishes for each received event, and when (pure: no rospy, time passed in).

The receive side (robopuppet.protocol.state_set) turns bytes into whole state sets and counted
heartbeats; this turns those into outputs, one namedtuple per message to publish:

- Heartbeat: one per counted heartbeat.
- JointStates, EncStatus, JointTopics: the joints of a set, only once the settings are loaded
  (loaded_since_s) and only from a set whose first frame arrived after that: before it, the
  device runs on firmware defaults (home_angle 0, sign_angle +1) and a set begun then may carry
  angles with the wrong offset or sign. EncStatus at once whenever a joint's status changes (and
  for every joint after each load).
- Grippers, Button and JointTopics: at most once per topic period (the cap of the per-joint
  topics); Button also at once whenever the button changes.
"""
import collections

from robopuppet import interface, settings
from robopuppet.protocol import codec

Heartbeat = collections.namedtuple('Heartbeat', '')
# rad, V in joint order; angle_tag: settings.angle_tag of the settings the device was being sent
JointStates = collections.namedtuple('JointStates', 'positions efforts angle_tag', defaults=('',))
EncStatus = collections.namedtuple('EncStatus', 'joint status')  # status: interface.ENC_STATUS
JointTopics = collections.namedtuple('JointTopics', 'angles voltages statuses')  # rad, V, text
Grippers = collections.namedtuple('Grippers', 'readings')  # four readings, 0-1
Button = collections.namedtuple('Button', 'button')  # 0 none, 1-4


class StateOutput:
    """Turn state_set events into the outputs to publish.

    Args:
        topic_period_s: the least time between two publications of a per-joint topic, s.
    """

    def __init__(self, topic_period_s):
        if not topic_period_s > 0.0:
            raise ValueError('the topic period must be positive, got %r' % (topic_period_s,))
        self._period_s = topic_period_s
        self._loaded_since_s = None
        self._positions = [0.0] * settings.NUM_JOINTS
        self._efforts = [0.0] * settings.NUM_JOINTS
        self._status = [None] * settings.NUM_JOINTS
        self._button = None
        self._next_topics_s = 0.0

    def on_events(self, events, now_s, loaded_since_s, angle_tag=''):
        """Return the outputs for events (state_set.StateSet, codec.Heartbeat) received at now_s.

        Args:
            loaded_since_s: when the settings were loaded after the last (re)connect, or None
                while they are not (same clock as now_s and the sets' start_s).
            angle_tag: the JointStates' tag (DeviceSettings.angle_tag now).
        """
        if loaded_since_s != self._loaded_since_s:
            self._loaded_since_s = loaded_since_s
            self._status = [None] * settings.NUM_JOINTS  # a new load: every enc_stat at once
        outputs = []
        for event in events:
            if type(event) is codec.Heartbeat:
                outputs.append(Heartbeat())
            else:
                self._on_set(event, now_s, outputs, angle_tag)
        return outputs

    def _on_set(self, state, now_s, outputs, angle_tag):
        joints = self._loaded_since_s is not None and state.start_s >= self._loaded_since_s
        if joints:
            for message in state.joints:
                joint = message.joint
                self._positions[joint] = message.angle_rad
                self._efforts[joint] = message.voltage_v
                status = interface.ENC_STATUS[message.status]
                if status != self._status[joint]:
                    self._status[joint] = status
                    outputs.append(EncStatus(joint, status))
            outputs.append(JointStates(tuple(self._positions), tuple(self._efforts), angle_tag))
        if state.button != self._button:
            self._button = state.button
            outputs.append(Button(state.button))
        if now_s >= self._next_topics_s:
            # Keep the average at most the cap, absorbing up to one period of arrival jitter.
            self._next_topics_s = max(self._next_topics_s + self._period_s, now_s - self._period_s)
            if joints:
                outputs.append(JointTopics(tuple(self._positions), tuple(self._efforts),
                                           tuple(self._status)))
            outputs.append(Grippers(tuple(state.grippers)))
            outputs.append(Button(self._button))
