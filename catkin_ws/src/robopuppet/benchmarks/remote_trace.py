"""What bench_remote.py measures besides the end-to-end latency: the per-hop times of a move
(Tracer: joint_states listeners on both hosts and the bed's packet trace) and the real-time
priority of the path's processes (--rt-path). bench_remote.py's docstring explains the hops."""
import json
import os
import struct
import subprocess
import time

import psutil
from robopuppet import interface

from netbed_testing import HELPERS

TRACE_KEEP_S = 2.0   # the forwarder keeps each packet this long for find
HOPS = ('sample', 'local', 'to bed', 'bed', 'bed late', 'robot rx', 'arm_R+')
RT_PATH = ('__name:=serial_R', '__name:=arm_R', 'command_stamps.py', 'ros_node.py listen')
RT_PATH_PRIORITY = 5  # below the bed's forwarder (tools/netbed/forwarder.py)
STATES_TOPIC = '%s/%s' % (interface.puppet_ns('R'), interface.JOINT_STATES)


class Listener:
    """A ros_node.py listener's output, read incrementally: [(t, msg)]."""

    def __init__(self, proc):
        self.proc, self.items, self._offset = proc, [], 0

    def update(self):
        with open(self.proc.log_path) as log:
            log.seek(self._offset)
            text = log.read()
        end = text.rfind('\n') + 1
        self._offset += len(text[:end].encode())
        for line in text[:end].splitlines():
            if line.startswith('{"t"'):
                item = json.loads(line)
                self.items.append((item['t'], item['msg']))
        return self.items


class Tracer:
    """Per-hop times of the moves (module docstring): the joint_states listeners on both hosts,
    and the bed's trace (bed None: no bed on the path, --one-host)."""

    def __init__(self, rb, operator, bed):
        node = str(HELPERS / 'ros_node.py')
        self.states = {host: Listener(rb.python(host, node, 'listen', STATES_TOPIC,
                                                'sensor_msgs/JointState', 'nodelay'))
                       for host in {operator, 'robot'}}
        self._operator, self._rb, self.bed = operator, rb, bed
        self._arm_ports = set()

    def marks(self):
        """Return where each listener's output ends now: the start of the next move's."""
        return {host: len(listener.update()) for host, listener in self.states.items()}

    def _arrival(self, host, marks, match):
        """Return (arrival, message) of the first message since marks that match() accepts."""
        deadline = time.monotonic() + 0.5
        while time.monotonic() < deadline:
            for t, msg in self.states[host].update()[marks[host]:]:
                if match(msg):
                    return t, msg
            time.sleep(0.005)
        return None, None

    def _arm_port(self, found):
        """Return the entry of `found` (forwarder find) that went to arm_R's socket, or None.
        (The robot host's listener gets its own copy of each sample.)"""
        for refresh in (False, True):
            if refresh:  # a port not seen yet: a new connection
                text = subprocess.run(self._rb.bed.command('robot', ['ss', '-tnpH']),
                                      capture_output=True, text=True).stdout
                self._arm_ports = {int(line.split()[3].rsplit(':', 1)[1])
                                   for line in text.splitlines() if '(("arm",' in line}
            for entry in found:
                if entry[3] in self._arm_ports:
                    return entry
        return None

    def hops(self, marks, angle, moved_wall, hit):
        """Return {hop: s} of one move (None: not measured) and the bed's delay of the packet
        that carried it to arm_R (s; None when not found or no bed on the path)."""
        out = dict.fromkeys(HOPS)
        local_t, msg = self._arrival(self._operator, marks,
                                     lambda m: abs(m['position'][6] - angle) < 1e-6)
        if msg is None:
            return out, None
        stamp = msg['header']['stamp']
        stamp_s = stamp['secs'] + stamp['nsecs'] * 1e-9
        out.update({'sample': stamp_s - moved_wall, 'local': local_t - stamp_s,
                    'arm_R+': hit - stamp_s})
        if self.bed is None:
            return out, None
        robot_t, _ = self._arrival('robot', marks, lambda m: m['header']['stamp'] == stamp)
        found = self.bed.request({'cmd': 'find', 'direction': 'to-robot', 'needle': struct.pack(
            '<II', stamp['secs'], stamp['nsecs']).hex()})['found']
        wall_minus_mono = time.time() - time.monotonic()  # one kernel clock; both read here
        arm = self._arm_port(found)
        other = [entry for entry in found if entry is not arm]
        if robot_t is not None and len(other) == 1:
            out['robot rx'] = robot_t - (other[0][2] + wall_minus_mono)
        if arm is None:
            out['arm_R+'] = None
            return out, None
        offered, release, written = (x + wall_minus_mono for x in arm[:3])
        out.update({'to bed': offered - stamp_s, 'bed': release - offered,
                    'bed late': written - release, 'arm_R+': hit - written})
        return out, release - offered


def prioritise(procs):
    """Give every thread of this process and of the path's processes started by procs (their
    descendants only: not other users' nodes) SCHED_FIFO RT_PATH_PRIORITY; return the
    psutil.Processes."""
    path = [psutil.Process()]
    for proc in procs:
        try:
            root = psutil.Process(proc.pid)
            path += [p for p in [root] + root.children(recursive=True)
                     if any(mark in ' '.join(p.cmdline()) for mark in RT_PATH)]
        except psutil.NoSuchProcess:
            continue
    schedule(path, os.SCHED_FIFO, RT_PATH_PRIORITY)
    return path


def schedule(processes, policy, priority):
    """Set the scheduling policy of every thread of the processes (those gone are skipped)."""
    for process in processes:
        try:
            threads = process.threads()
        except psutil.NoSuchProcess:
            continue
        for thread in threads:
            try:
                os.sched_setscheduler(thread.id, policy, os.sched_param(priority))
            except ProcessLookupError:
                pass
