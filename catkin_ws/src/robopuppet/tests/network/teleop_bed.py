"""The teleop tests' two hosts on the bed (test_teleop_remote.py): robot.launch on the robot host,
operator.launch with the simulated puppet (comm_rate 10, the 2020 firmware's rate) on the
operator host, the hand (helpers/puppet_hand.py), listeners on both hosts (helpers/ros_node.py)
and a stall probe (helpers/stall_probe.py); and what their records tell about the link and the
machine.
"""
import json
import os
import re
import sys
import time

from robopuppet import baxter_description, interface
from robopuppet.arm import timing

from netbed_testing import HELPERS

sys.path.insert(0, str(HELPERS.parent.parent / 'integration'))
from hand_pose import HAND_POSE  # noqa: E402

NODE = str(HELPERS / 'ros_node.py')
HAND = str(HELPERS / 'puppet_hand.py')
PROBE = str(HELPERS / 'stall_probe.py')
SIDE = 'R'
POSE = HAND_POSE
COMM_RATE_HZ = 10.0
MAX_SAMPLE_AGE_S = 0.35
NAMES = baxter_description.arm_joint_names('right')
STATE_TIMEOUT_S = timing.state_timeout(COMM_RATE_HZ).timeout_s   # 0.4 s
HOST_STALL_S = 0.3          # serial_R's own stamps this far apart: the operator host stalled
PROBE_STALL_S = 0.15        # an idle process scheduled this late: the machine stalled
HELD_S = 0.2                # a sample this long in transit was held back (TCP resending)


class Stream:
    """The JSON lines of a helper's log, read incrementally: [(t, msg)] of `listen` helpers."""

    def __init__(self, proc):
        self.proc = proc
        self.items = []
        self._offset = 0

    def update(self):
        try:
            with open(self.proc.log_path) as log:
                log.seek(self._offset)
                text = log.read()
        except OSError:
            return self.items
        end = text.rfind('\n') + 1
        self._offset += len(text[:end].encode())
        for line in text[:end].splitlines():
            if line.startswith('{'):
                try:
                    item = json.loads(line)
                except ValueError:
                    continue
                if 'msg' in item:
                    self.items.append((item['t'], item['msg']))
        return self.items

    def since(self, t):
        return [item for item in self.update() if item[0] > t]

    def last(self):
        items = self.update()
        return items[-1][1] if items else None


class System:
    """The two hosts' launch files, the hand, and the observers on both hosts."""

    def __init__(self, rb):
        self.rb = rb
        self._commands, self._next_id = [], 0
        self.command_file = rb.work_dir / 'hand_commands.jsonl'
        self.command_file.write_text('')
        rb.roscore()
        common = ('run_side_L:=false', 'comm_rate:=%g' % COMM_RATE_HZ,
                  'max_sample_age:=%g' % MAX_SAMPLE_AGE_S)
        rb.roslaunch('robot', 'robot.launch', 'gripper_calibrated:=true', *common)
        rb.roslaunch('operator', 'operator.launch', 'sim_puppet:=true', 'gui:=false',
                     'rviz:=false', 'record_sides:=R', 'sim_link_prefix:=%s/pty' % rb.work_dir,
                     *common)
        ns = interface.puppet_ns(SIDE)
        listen = lambda host, topic, kind: Stream(rb.python(host, NODE, 'listen', topic, kind))
        self.commands = listen('robot', interface.limb_topic('right', 'joint_command'),
                               'baxter_core_msgs/JointCommand')
        self.baxter = listen('robot', interface.ROBOT_JOINT_STATES, 'sensor_msgs/JointState')
        self.robot_teleop = listen('robot', '%s/%s' % (ns, interface.TELEOP_STATE),
                                   'robopuppet_msgs/TeleopState')
        self.op_teleop = listen('operator', '%s/%s' % (ns, interface.TELEOP_STATE),
                                'robopuppet_msgs/TeleopState')
        # What gui_R hears of arm_R, recovering after a cut as gui_R does (link_recovery).
        self.op_link = Stream(rb.python('operator', NODE, 'listen', '%s/%s' % (
            ns, interface.LINK_STATE), 'robopuppet_msgs/LinkState', 'recover'))
        self.puppet = listen('operator', '%s/%s' % (ns, interface.JOINT_STATES),
                             'sensor_msgs/JointState')
        # The puppet's samples on the robot host, over a TCP connection of their own that
        # losses hit as they hit arm_R's (tcp_nodelay, as arm_R asks): what the link does.
        self.puppet_robot = Stream(rb.python('robot', NODE, 'listen', '%s/%s' % (
            ns, interface.JOINT_STATES), 'sensor_msgs/JointState', 'nodelay'))
        self.probe = rb.python('robot', PROBE)
        self.hand = rb.python('operator', HAND, SIDE, self.command_file)
        self.hand.wait_for(lambda p: any(line.get('ready') for line in p.json_lines()), 60,
                           'the hand helper ready')

    def do(self, op, timeout_s=60.0, **args):
        """Have the hand helper carry out op; wait until it is done."""
        self._next_id += 1
        command_id = self._next_id
        self._commands.append(json.dumps(dict(args, id=command_id, op=op)))
        tmp = self.command_file.with_suffix('.tmp')
        tmp.write_text('\n'.join(self._commands) + '\n')
        os.replace(tmp, self.command_file)

        def finished(proc):
            for line in proc.json_lines():
                if line.get('failed') == command_id:
                    raise AssertionError('hand: %s failed: %s\n%s' % (
                        op, line['error'], '\n'.join(p.tail(1500) for p in self.rb.procs)))
                if line.get('done') == command_id:
                    return line
            return None
        return self.hand.wait_for(finished, timeout_s, 'hand op %s done' % op)

    def robot_state(self):
        msg = self.robot_teleop.last()
        return msg and msg['state']

    def wait(self, condition, timeout_s, what):
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            value = condition()
            if value:
                return value
            time.sleep(0.1)
        raise AssertionError('no %s within %.0f s (robot teleop_state: %s)\n%s' % (
            what, timeout_s, self.robot_teleop.last(),
            '\n'.join(p.tail(1500) for p in self.rb.procs)))

    def baxter_arm(self, since_t=0.0):
        """Return [(t, 7 angles of Baxter's right arm)] measured after since_t."""
        out = []
        for t, msg in self.baxter.since(since_t):
            where = dict(zip(msg['name'], msg['position']))
            if all(name in where for name in NAMES):
                out.append((t, [where[name] for name in NAMES]))
        return out

    def baxter_on(self, pose, tolerance_rad=0.01):
        """Return whether Baxter's right arm, as last measured, is within tolerance of pose."""
        recent = self.baxter_arm(time.time() - 0.5)
        return bool(recent) and bool(pose) and max_error(recent[-1][1], pose) < tolerance_rad

    def puppet_angles(self):
        msg = self.puppet.last()
        return msg and msg['position']

    def follow(self, timeout_s=60.0):
        """Press button 3 and wait until the robot host reports following. A press that comes
        while a stall of the machine faults the teleop does nothing: once ready, press again."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            self.wait(lambda: self.robot_state() == interface.READY, 20, 'ready')
            self.do('press', button=interface.BUTTON_RIGHT)
            pressed = time.monotonic()
            while time.monotonic() < pressed + 5.0:
                if self.robot_state() == interface.FOLLOWING:
                    return
                time.sleep(0.1)
        self.wait(lambda: self.robot_state() == interface.FOLLOWING, 1, 'following')

    def stop_following(self):
        """Leave with Baxter not following (press 3 when it follows), after any fault."""
        if self.robot_state() == interface.FOLLOWING:
            self.do('press', button=interface.BUTTON_RIGHT)
        self.wait(lambda: self.robot_state() in (interface.READY, interface.FAULT), 20,
                  'not following')


def max_error(a, b):
    return max(abs(x - y) for x, y in zip(a, b))


def stamp_s(msg):
    return msg['header']['stamp']['secs'] + msg['header']['stamp']['nsecs'] * 1e-9


def machine_stall(system, since_t, until_t):
    """Return why a stop or a tracking error between since_t and until_t (time.time()) says
    nothing about the link, or '': the puppet's stream paused on the operator host itself
    (serial_R's stamps over HOST_STALL_S apart, before any network), an idle process
    (helpers/stall_probe.py) was not scheduled for PROBE_STALL_S (the bed's forwarder, the link
    itself, starves as well), or arm_R's command loop stalled (its own watchdog says so). Each
    stops Baxter, rightly, on a machine that other work starves."""
    stamps = [stamp_s(m) for t, m in system.puppet.since(since_t - 1.0) if t <= until_t + 1.0]
    gap_s = max([b - a for a, b in zip(stamps, stamps[1:])] + [0.0])
    if gap_s > HOST_STALL_S:
        return 'the puppet stream paused %.2f s on the operator host itself' % gap_s
    stall_s = max([line['stall_s'] for line in system.probe.json_lines()
                   if since_t - 1.0 <= line.get('t', 0.0) <= until_t + 1.0] + [0.0])
    if stall_s > PROBE_STALL_S:
        return 'an idle process on the machine was scheduled %.2f s late' % stall_s
    return next(('arm_R stalled: %s' % m['detail'] for _, m in system.robot_teleop.since(since_t)
                 if 'the arm controller failed' in m['detail']), '')


def held_past_the_timeout(system, since_t):
    """Return why arm_R's stop after since_t was one that the design calls for, or '': a sample
    arrived STATE_TIMEOUT_S old or older (its age in the fault's detail). TCP held it back (a
    lost resend, or one recovered by the retransmission timer), or a starved arm_R took it late,
    longer than the state timeout bridges, and the samples behind it waited too: silence, which
    stops Baxter. Samples held back less are dropped or used and must not stop Baxter."""
    ages = [float(age) for _, m in system.robot_teleop.since(since_t)
            if m['state'] == interface.FAULT for age in re.findall(r'(\d+\.\d+) s old',
                                                                    m['detail'])]
    if max(ages + [0.0]) >= STATE_TIMEOUT_S:
        return 'a sample arrived %.3f s old, held back past the state timeout' % max(ages)
    return ''


def link_figures(system, since_t, until_t):
    """Return what the link did to the puppet's samples between since_t and until_t: how many
    TCP held back (HELD_S or more in transit to the robot host) and the longest transit, the
    late samples arm_R dropped (its link_state, on the operator host) and the oldest."""
    transit = [t - stamp_s(m) for t, m in system.puppet_robot.since(since_t) if t <= until_t]
    reports = [m for t, m in system.op_link.since(since_t) if t <= until_t]
    dropped = [m for m in reports if 'dropped' in m['detail'] or 'too late' in m['detail']]
    return ('%d of %d samples held back over %.1f s in transit (longest %.3f s); arm_R reported '
            'dropped late samples in %d of %d link_states (sample ages up to %.3f s)' % (
                sum(x >= HELD_S for x in transit), len(transit), HELD_S, max(transit + [0.0]),
                len(dropped), len(reports), max([m['sample_age'] for m in reports] + [0.0])))
