"""recorder: demonstration episodes as rosbags, started and stopped by button 4 or a service."""
import io
import os
import socket
import sys
import threading
import time
import xmlrpc.client

import rosgraph
import rosgraph.network
import rospkg
import rospy
import rospy.client
from rospy.impl.validators import ParameterInvalid
from std_msgs.msg import UInt8

from robopuppet import interface
from robopuppet.config import config_file
from robopuppet.episodes import episode_files, recording
from robopuppet.episodes.session import Recorder
from robopuppet.link_recovery import LinkRecovery
from robopuppet.periodic import Guard, Loop
from robopuppet_msgs.msg import RecordingState
from robopuppet_msgs.srv import Record, RecordResponse

FLUSH_PERIOD_S = 0.5   # a kill loses at most this much (plus what is still in flight)
STATUS_EVERY = 2       # publish the status every this many flushes (once a second)
QUEUE_SIZE = 200       # per topic: 2 s of a 100 Hz topic while a flush holds the lock
NODE_NAME = 'recorder'
PROBE_TIMEOUT_S = 2.0  # a /puppet/record provider that does not answer a probe within is not live


class RecorderNode:
    """Record episodes (docs/demonstrations.md): the recorded sides', Baxter's and cameras' topics.

    Subscribes (rospy.AnyMsg, written raw with their arrival ROS time): always the user_btn of
        ~sides (a new press of button 4 starts or stops an episode); only while an episode runs
        the other recording.episode_topics of ~sides and ~cameras, subscribed at its start (so
        latched topics deliver their newest message then) and unregistered at its stop.
    Serves: /puppet/record (robopuppet_msgs/Record).
    Publishes: /puppet/recording (robopuppet_msgs/RecordingState, latched): on every change
        and once a second while recording.
    Holds the episodes folder's episode_files.FolderLock (main takes it before the node
    registers; one recorder per folder) and repairs, under it, what the folder holds of episodes
    that did not end (episode_files.recover).
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

    def __init__(self, directory, folder):
        """directory: the episodes folder (episodes_dir); folder: its held FolderLock, or None
        when it could not be taken (the node tries again at each start and records only under
        it)."""
        sides = recording.parse_sides(rospy.get_param('~sides', 'LR'))
        cameras = recording.parse_cameras(rospy.get_param('~cameras',
                                                          list(interface.SIM_CAMERAS)))
        self._sim = bool(rospy.get_param('~sim', False))
        self._lock = threading.Lock()     # the Recorder, the episode number, the status
        self._switch = threading.Lock()   # one start or stop (and its subscriptions) at a time
        self._recorder = Recorder(directory, sides, cameras,
                                  float(rospy.get_param('~min_free_mb',
                                                        recording.DEFAULT_MIN_FREE_MB)),
                                  episode_files)
        self._folder = folder
        if folder is not None:
            self._repair()
        problem = self._claim()
        if problem:
            rospy.logwarn('%s: episodes are refused until it can be', problem)
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
        # After a cut: connect anew to the robot host's publishers once Baxter's stream is stuck.
        LinkRecovery(rospy.get_name(), [interface.ROBOT_JOINT_STATES]).start()
        rospy.on_shutdown(self._shutdown)
        rospy.loginfo('recording sides %s and cameras %s into %s (button %d or %s)',
                      ''.join(sides), ', '.join(cameras) or 'none', self._recorder.directory,
                      recording.RECORD_BUTTON, recording.RECORD_SERVICE)

    def _claim(self):
        """Take the folder's lock unless held (then repair); return '' or why it cannot."""
        if self._folder is None:
            try:
                self._folder = episode_files.FolderLock(self._recorder.directory,
                                                        rospy.get_name())
            except episode_files.FolderBusy as error:
                return str(error)
            except OSError as error:
                return 'cannot lock %s: %s' % (self._recorder.directory, error)
            self._repair()
        return ''

    def _repair(self):
        for path, repaired, error in episode_files.recover(self._folder):
            if error:
                rospy.logerr('cannot repair %s: %s', path, error)
            else:
                rospy.logwarn('repaired %s, left by an episode that did not end%s (%s)',
                              repaired, '' if path.endswith(recording.ACTIVE) else
                              ' (it had no index)', 'ended_cleanly: false')

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
            problem = self._claim()
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


def record_provider(master, caller_id):
    """Return who serves RECORD_SERVICE live, e.g. '/recorder (pid 4242)', or '' when nobody:
    not registered, or registered by a process that is gone (the master keeps a killed node's
    registration) or does not answer a probe within PROBE_TIMEOUT_S."""
    try:
        address = rospy.core.parse_rosrpc_uri(master.lookupService(recording.RECORD_SERVICE))
        with socket.create_connection(address, PROBE_TIMEOUT_S) as sock:
            sock.settimeout(PROBE_TIMEOUT_S)
            rosgraph.network.write_ros_handshake_header(sock, {
                'probe': '1', 'md5sum': '*', 'callerid': caller_id,
                'service': recording.RECORD_SERVICE})
            header = rosgraph.network.read_ros_handshake_header(sock, io.BytesIO(), 4096)
    except (rosgraph.MasterException, ParameterInvalid, OSError,
            rosgraph.network.ROSHandshakeException):
        return ''
    if 'error' in header:
        return ''  # the port is another node's now
    node = header.get('callerid', 'an unknown node')
    timeout_s = socket.getdefaulttimeout()
    socket.setdefaulttimeout(PROBE_TIMEOUT_S)
    try:
        pid = xmlrpc.client.ServerProxy(master.lookupNode(node)).getPid(caller_id)[2]
    except (rosgraph.MasterException, OSError, xmlrpc.client.Error, LookupError, TypeError):
        return node
    finally:
        socket.setdefaulttimeout(timeout_s)
    return '%s (pid %s)' % (node, pid)


def _episodes_dir(master, node, argv):
    """Return ~episodes_dir (absolute) as rospy will see it, before the node registers."""
    params = rospy.client.load_command_line_node_params(argv)
    value = params.get('episodes_dir')
    if value is None:
        try:
            value = master.getParam(rosgraph.names.ns_join(node, 'episodes_dir'))
        except rosgraph.MasterException:
            value = ''
    return os.path.abspath(os.path.expanduser(str(value or '') or recording.episodes_dir(
        rospkg.get_ros_home())))


def _refuse(why):
    sys.stderr.write('recorder: refused: %s\n' % why)
    sys.exit(2)


def main():
    """Run the recorder node until ROS shuts down; refuse (exit code 2, no episode touched, nothing
    registered with the master) when a live recorder holds the episodes folder or serves
    RECORD_SERVICE (rospy would take that over from it)."""
    argv = sys.argv
    node = rosgraph.names.ns_join(rosgraph.names.get_ros_namespace(argv=argv),
                                  rosgraph.names.load_mappings(argv).get('__name', NODE_NAME))
    master = rosgraph.Master(node)
    while not rosgraph.is_master_online(master.master_uri):
        time.sleep(0.5)  # as rospy.init_node would wait for it
    directory = _episodes_dir(master, node, argv)
    folder = None
    try:
        folder = episode_files.FolderLock(directory, node)
    except episode_files.FolderBusy as error:
        _refuse(error)
    except OSError:
        pass  # the node says why and tries again at each start
    provider = record_provider(master, node)
    if provider:
        _refuse('%s is served already by %s: one recorder per ROS master (rospy would take '
                'the service over from it); stop that one first' % (
                    recording.RECORD_SERVICE, provider))
    rospy.init_node(NODE_NAME)
    RecorderNode(directory, folder)
    rospy.spin()
