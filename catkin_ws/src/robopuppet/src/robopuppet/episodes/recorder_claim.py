"""The recorder's claims: its episodes folder (one recorder per folder, episode_folder's lock)
and RECORD_SERVICE (one recorder per ROS master), checked before the node registers.

A folder whose lock could not be taken at the start is tried again at each episode's start
(FolderHold); what the folder holds of episodes that did not end is repaired under the lock.
"""
import io
import os
import socket
import sys
import time
import xmlrpc.client

import rosgraph
import rosgraph.network
import rospkg
import rospy
import rospy.client
from rospy.impl.validators import ParameterInvalid

from robopuppet import interface
from robopuppet.episodes import episode_files, recording
from robopuppet.episodes.episode_folder import FolderBusy, FolderLock

PROBE_TIMEOUT_S = 2.0  # a /puppet/record provider that does not answer a probe within is not live


class FolderHold:
    """Hold an episodes folder's FolderLock, taken now or at a later claim(), and repair the
    folder (episode_files.recover) once it is held.

    Args:
        directory: the episodes folder.
        lock: its held FolderLock, or None when it could not be taken yet.
        owner: what the lock file names as the holder (the node's name).
    """

    def __init__(self, directory, lock, owner):
        self.directory, self._lock, self._owner = directory, lock, owner
        self._repaired = False

    def claim(self):
        """Take the lock unless held, repair under it once; return '' or why it cannot."""
        if self._lock is None:
            try:
                self._lock = FolderLock(self.directory, self._owner)
            except FolderBusy as error:
                return str(error)
            except OSError as error:
                return 'cannot lock %s: %s' % (self.directory, error)
        if not self._repaired:
            self._repaired = True
            for path, repaired, error in episode_files.recover(self._lock):
                if error:
                    rospy.logerr('cannot repair %s: %s', path, error)
                else:
                    rospy.logwarn('repaired %s, left by an episode that did not end%s (%s)',
                                  repaired, '' if path.endswith(recording.ACTIVE) else
                                  ' (it had no index)', 'ended_cleanly: false')
        return ''


def record_provider(master, caller_id):
    """Return who serves RECORD_SERVICE live, e.g. '/recorder (pid 4242)', or '' when nobody:
    not registered, or registered by a process that is gone (the master keeps a killed node's
    registration) or does not answer a probe within PROBE_TIMEOUT_S."""
    try:
        address = rospy.core.parse_rosrpc_uri(master.lookupService(interface.RECORD_SERVICE))
        with socket.create_connection(address, PROBE_TIMEOUT_S) as sock:
            sock.settimeout(PROBE_TIMEOUT_S)
            rosgraph.network.write_ros_handshake_header(sock, {
                'probe': '1', 'md5sum': '*', 'callerid': caller_id,
                'service': interface.RECORD_SERVICE})
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


def claim(argv, default_name):
    """Return (the node's episodes folder, its FolderLock or None) before the node registers;
    refuse (exit code 2, no episode touched, nothing registered with the master) when a live
    recorder holds the folder or serves RECORD_SERVICE (rospy would take that over from it)."""
    node = rosgraph.names.ns_join(rosgraph.names.get_ros_namespace(argv=argv),
                                  rosgraph.names.load_mappings(argv).get('__name', default_name))
    master = rosgraph.Master(node)
    while not rosgraph.is_master_online(master.master_uri):
        time.sleep(0.5)  # as rospy.init_node would wait for it
    directory = _episodes_dir(master, node, argv)
    lock = None
    try:
        lock = FolderLock(directory, node)
    except FolderBusy as error:
        _refuse(error)
    except OSError:
        pass  # the node says why and tries again at each start
    provider = record_provider(master, node)
    if provider:
        _refuse('%s is served already by %s: one recorder per ROS master (rospy would take '
                'the service over from it); stop that one first' % (
                    interface.RECORD_SERVICE, provider))
    return directory, lock
