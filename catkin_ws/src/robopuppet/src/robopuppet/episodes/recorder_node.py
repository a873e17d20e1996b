"""recorder: demonstration episodes as rosbags, started and stopped by button 4 or a service."""
import os
import threading
import time

import rospkg
import rospy
from std_msgs.msg import UInt8

from robopuppet import interface
from robopuppet.config import config_file
from robopuppet.episodes import episode_files, recording
from robopuppet.episodes.session import Recorder
from robopuppet.periodic import Guard, Loop
from robopuppet_msgs.msg import RecordingState
from robopuppet_msgs.srv import Record, RecordResponse

FLUSH_PERIOD_S = 0.5   # a kill loses at most this much (plus what is still in flight)
STATUS_EVERY = 2       # publish the status every this many flushes (once a second)
QUEUE_SIZE = 200       # per topic: 2 s of a 100 Hz topic while a flush holds the lock


class RecorderNode:
    """Record episodes (docs/demonstrations.md): the recorded sides', Baxter's and cameras' topics.

    Subscribes (rospy.AnyMsg, written raw with their arrival ROS time): always the user_btn of
        ~sides (a new press of button 4 starts or stops an episode); only while an episode runs
        the other recording.episode_topics of ~sides and ~cameras, subscribed at its start (so
        latched topics deliver their newest message then) and unregistered at its stop.
    Serves: /puppet/record (robopuppet_msgs/Record).
    Publishes: /puppet/recording (robopuppet_msgs/RecordingState, latched): on every change
        and once a second while recording.
    At start, repairs every leftover <name>.bag.active (reindex, rename, ended_cleanly false).
    Parameters:
        ~sides (str, default 'LR'): the puppet sides recorded, e.g. 'R'.
        ~cameras (list of str, default interface.SIM_CAMERAS: room_camera,
            left_hand_camera, right_hand_camera): the cameras whose image/compressed is recorded.
        ~episodes_dir (str, default ''): where episodes go; '' is $ROS_HOME/robopuppet/episodes.
        ~min_free_mb (float, default 200): free space (MB) below which an episode neither
            starts nor goes on.
        ~sim (bool, default false): recorded against the simulated system (metadata sim).
        The metadata also reads /arm_<side>/comm_rate and /config_<side>/file_name.
    """

    def __init__(self):
        sides = recording.parse_sides(rospy.get_param('~sides', 'LR'))
        cameras = recording.parse_cameras(rospy.get_param('~cameras',
                                                          list(interface.SIM_CAMERAS)))
        directory = rospy.get_param('~episodes_dir', '') or recording.episodes_dir(
            rospkg.get_ros_home())
        self._sim = bool(rospy.get_param('~sim', False))
        self._lock = threading.Lock()     # the Recorder, the episode number, the status
        self._switch = threading.Lock()   # one start or stop (and its subscriptions) at a time
        self._recorder = Recorder(os.path.expanduser(directory), sides, cameras,
                                  float(rospy.get_param('~min_free_mb',
                                                        recording.DEFAULT_MIN_FREE_MB)),
                                  episode_files)
        self._repair_leftovers()
        self._episode_topics = recording.episode_topics(sides, cameras)
        self._subscribers = []   # the running episode's (under _switch)
        self._number = 0         # of the newest episode: late messages of older ones are dropped
        self._ticks = 0
        self._status_pub = rospy.Publisher(recording.RECORDING_TOPIC, RecordingState,
                                           queue_size=1, latch=True)
        self._publish()
        self._edges = {}
        for topic in recording.button_topics(sides):
            self._edges[topic] = recording.ButtonEdge()
            rospy.Subscriber(topic, rospy.AnyMsg, self._on_button, callback_args=topic,
                             queue_size=QUEUE_SIZE)
        self._service = rospy.Service(recording.RECORD_SERVICE, Record, self._on_record)
        guard = Guard(rospy.get_name(), rospy.logerr)
        self._loop = Loop(guard, 'recorder flush', FLUSH_PERIOD_S, self._tick).start()
        rospy.on_shutdown(self._shutdown)
        rospy.loginfo('recording sides %s and cameras %s into %s (button %d or %s)',
                      ''.join(sides), ', '.join(cameras) or 'none', directory,
                      recording.RECORD_BUTTON, recording.RECORD_SERVICE)

    def _repair_leftovers(self):
        for path in episode_files.leftovers(self._recorder.directory):
            try:
                rospy.logwarn('repaired %s, left by an episode that did not end (%s)',
                              episode_files.repair(path), 'ended_cleanly: false')
            except Exception as error:  # pylint: disable=broad-except
                rospy.logerr('cannot repair %s (left as it is): %s', path, error)

    def _context(self):
        """Return what the metadata needs of the running system."""
        side = self._recorder.sides[0]
        rate = rospy.get_param('/arm_%s/comm_rate' % side, None)
        fingerprints = {s: episode_files.ini_fingerprint(config_file.resolve_path(
            rospy.get_param('/config_%s/file_name' % s, 'arm_%s.ini' % s),
            rospkg.get_ros_home())) for s in self._recorder.sides}
        return rate, fingerprints, self._sim

    def _start(self, notes):
        context = self._context()
        with self._switch:
            self._unsubscribe()  # those of an episode that stopped itself (disk, write error)
            with self._lock:
                answer = self._recorder.start(notes, rospy.get_time(), time.time(), *context)
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
        answer = self._start(request.notes) if request.start else self._stop(request.notes)
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
    """Run the recorder node until ROS shuts down."""
    rospy.init_node('recorder')
    RecorderNode()
    rospy.spin()
