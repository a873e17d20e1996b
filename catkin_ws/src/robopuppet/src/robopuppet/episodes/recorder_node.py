"""recorder: demonstration episodes as rosbags, started and stopped by button 4 or a service."""
import sys
import threading
import time

import rospy
from std_msgs.msg import UInt8

from robopuppet import interface
from robopuppet.episodes import recording
from robopuppet.episodes.recorder_claim import FolderHold, claim
from robopuppet.episodes.recorder_params import make_recorder, running_system
from robopuppet.link_recovery import LinkRecovery
from robopuppet.periodic import Guard, Loop
from robopuppet_msgs.msg import RecordingState
from robopuppet_msgs.srv import Record, RecordResponse

FLUSH_PERIOD_S = 0.5   # a kill loses at most this much (plus what is still in flight)
STATUS_EVERY = 2       # publish the status every this many flushes (once a second)
QUEUE_SIZE = 200       # per topic: 2 s of a 100 Hz topic while a flush holds the lock
NODE_NAME = 'recorder'


class RecorderNode:
    """Record episodes (docs/demonstrations.md): the recorded sides', Baxter's and cameras' topics.

    Subscribes (rospy.AnyMsg, written raw with their arrival ROS time): always the user_btn of
        ~sides (a new press of button 4 starts or stops an episode); only while an episode runs
        the other recording.episode_topics of ~sides and ~cameras, subscribed at its start (so
        latched topics deliver their newest message then) and unregistered at its stop.
    Serves: /puppet/record (robopuppet_msgs/Record).
    Publishes: /puppet/recording (robopuppet_msgs/RecordingState, latched): on every change
        and once a second while recording.
    Holds the episodes folder's lock (recorder_claim: main takes it before the node registers;
    one recorder per folder) and repairs, under it, what the folder holds of episodes that did
    not end.
    Parameters:
        ~sides (str, default 'LR'): the puppet sides recorded, e.g. 'R'.
        ~cameras (list of str, default interface.SIM_CAMERAS: room_camera,
            left_hand_camera, right_hand_camera): the cameras whose image/compressed is recorded.
        ~episodes_dir (str, default ''): where episodes go; '' is $ROS_HOME/robopuppet/episodes.
        ~min_free_mb (float, default 200): free space (MB) below which an episode neither
            starts nor goes on.
        ~sim (bool, default false): recorded against the simulated system (metadata sim).
        ~task (str, default ''): the metadata's task of an episode started without one (button
            4, or a Record request whose task is empty); one printable line, at most
            recording.TASK_MAX_CHARS characters, else such a start is refused.
        The metadata also reads /arm_<side>/comm_rate and /config_<side>/file_name.
    """

    def __init__(self, directory, folder):
        """directory: the episodes folder (episodes_dir); folder: its held FolderLock, or None
        (tried again at each start: episodes are recorded only under it)."""
        self._recorder, self._sim = make_recorder(directory)
        sides, cameras = self._recorder.sides, self._recorder.cameras
        self._lock = threading.Lock()     # the Recorder, the episode number, the status
        self._switch = threading.Lock()   # one start or stop (and its subscriptions) at a time
        self._folder = FolderHold(directory, folder, rospy.get_name())
        problem = self._folder.claim()
        if problem:
            rospy.logwarn('%s: episodes are refused until it can be', problem)
        self._episode_topics = recording.episode_topics(sides, cameras)
        self._subscribers = []   # the running episode's (under _switch)
        self._number = 0         # of the newest episode: late messages of older ones are dropped
        self._ticks = 0
        self._status_pub = rospy.Publisher(interface.RECORDING_TOPIC, RecordingState,
                                           queue_size=1, latch=True)
        self._publish()
        self._edges = {}
        for topic in recording.button_topics(sides):
            self._edges[topic] = recording.ButtonEdge()
            rospy.Subscriber(topic, rospy.AnyMsg, self._on_button, callback_args=topic,
                             queue_size=QUEUE_SIZE)
        self._service = rospy.Service(interface.RECORD_SERVICE, Record, self._on_record)
        guard = Guard(rospy.get_name(), rospy.logerr)
        self._loop = Loop(guard, 'recorder flush', FLUSH_PERIOD_S, self._tick).start()
        # After a cut: connect anew to the robot host's publishers once Baxter's stream is stuck.
        LinkRecovery(rospy.get_name(), [interface.ROBOT_JOINT_STATES]).start()
        rospy.on_shutdown(self._shutdown)
        rospy.loginfo('recording sides %s and cameras %s into %s (button %d or %s)',
                      ''.join(sides), ', '.join(cameras) or 'none', self._recorder.directory,
                      interface.BUTTON_RECORD, interface.RECORD_SERVICE)

    def _start(self, notes, task=''):
        context = running_system(self._recorder.sides) + (self._sim, task)
        with self._switch:
            self._unsubscribe()  # those of an episode that stopped itself (disk, write error)
            problem = self._folder.claim()
            with self._lock:
                answer = self._recorder.refuse(problem) if problem else self._recorder.start(
                    notes, rospy.get_time(), time.time(), *context)
                self._number += 1
                self._publish()
            if answer[0]:
                # Subscribed after the start, so that the first messages and the latched ones
                # (delivered on connecting) are written as they arrive.
                self._subscribers = [
                    rospy.Subscriber(topic, rospy.AnyMsg, self._on_message,
                                     callback_args=(topic, self._number), queue_size=QUEUE_SIZE)
                    for topic in self._episode_topics]
        self._log('started', answer)
        return answer

    def _stop(self, notes):
        with self._switch:
            with self._lock:
                answer = self._recorder.stop(notes, rospy.get_time())
                self._publish()
            self._unsubscribe()
        self._log('stopped', answer)
        return answer

    def _unsubscribe(self):
        """Unregister the episode's subscriptions (call under _switch)."""
        for subscriber in self._subscribers:
            subscriber.unregister()
        self._subscribers = []

    @staticmethod
    def _log(what, answer):
        ok, error, episode = answer
        if ok:
            rospy.loginfo('%s episode %s', what, episode)
        else:
            rospy.logwarn('not %s: %s', what, error)

    def _on_record(self, request):
        if request.start:
            answer = self._start(request.notes, request.task)
        else:
            answer = self._stop(request.notes)
        return RecordResponse(*answer)

    def _on_message(self, msg, topic_and_number):
        """Write a message into episode number (None: whichever runs) if that one runs."""
        stamp_s = rospy.get_time()
        topic, number = topic_and_number
        with self._lock:
            if number in (None, self._number) and self._recorder.write(topic, msg, stamp_s):
                self._publish()

    def _on_button(self, msg, topic):
        self._on_message(msg, (topic, None))
        if self._edges[topic].update(UInt8().deserialize(msg._buff).data):
            if self._recorder.recording():
                self._stop('')
            else:
                self._start('')

    def _tick(self):
        with self._lock:
            was = self._recorder.recording()
            self._recorder.tick(rospy.get_time())
            self._ticks += 1
            if self._ticks % STATUS_EVERY == 0 or was != self._recorder.recording():
                self._publish()
        if self._subscribers and not self._recorder.recording():
            with self._switch:  # an episode that stopped itself (disk, write error)
                if not self._recorder.recording():
                    self._unsubscribe()

    def _publish(self):
        status = self._recorder.status(rospy.get_time())
        msg = RecordingState(**status._asdict())
        msg.header.stamp = rospy.Time.now()
        self._status_pub.publish(msg)

    def _shutdown(self):
        self._loop.stop()
        if self._recorder.recording():
            self._stop('')


def main():
    """Run the recorder node until ROS shuts down, once recorder_claim.claim let it start."""
    directory, folder = claim(sys.argv, NODE_NAME)
    rospy.init_node(NODE_NAME)
    RecorderNode(directory, folder)
    rospy.spin()
