"""Teleoperation across the bed (issue 9): robot.launch on the robot host, operator.launch with
the simulated puppet (comm_rate 10, the 2020 firmware's rate) on the operator host, the right
puppet driving Baxter's right arm over a delayed, lossy link that gets cut and slowed.

Both launch files start once per module; each test starts from a calibrated puppet with Baxter
not following and a clean link. The hand is a helper on the operator host (helpers/
puppet_hand.py); what Baxter is told and does is recorded on the robot host, what the operator
would see (teleop_state, link_state) on the operator host (helpers/ros_node.py listeners).

Needs root (skipped otherwise) and ROS (`. tools/env.sh`). Run: tools/run_tests.py network.
"""
import bisect
import json
import math
import os
import time

import pytest

from robopuppet import baxter_description, interface

from netbed_testing import HELPERS

NODE = str(HELPERS / 'ros_node.py')
HAND = str(HELPERS / 'puppet_hand.py')
SIDE = 'R'
POSE = [0.2, 0.4, 0.3, 1.0, -0.3, 0.6, 0.25]
COMM_RATE_HZ = 10.0
MAX_SAMPLE_AGE_S = 0.35
APPROACH_SPEED_RAD_S = 0.5
NAMES = baxter_description.arm_joint_names('right')
LIMITS = baxter_description.arm_limits('right')
RECEPTION_JITTER_S = 0.03   # a listener's reception times jitter on a loaded machine


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
        self.op_link = listen('operator', '%s/%s' % (ns, interface.LINK_STATE),
                              'robopuppet_msgs/LinkState')
        self.puppet = listen('operator', '%s/%s' % (ns, interface.JOINT_STATES),
                             'sensor_msgs/JointState')
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

    def follow(self):
        """Press button 3 and wait until the robot host reports following."""
        self.do('press', button=interface.BUTTON_RIGHT)
        self.wait(lambda: self.robot_state() == interface.FOLLOWING, 20, 'following')

    def stop_following(self):
        """Leave with Baxter not following (press 3 when it follows), after any fault."""
        if self.robot_state() == interface.FOLLOWING:
            self.do('press', button=interface.BUTTON_RIGHT)
        self.wait(lambda: self.robot_state() in (interface.READY, interface.FAULT), 20,
                  'not following')


def max_error(a, b):
    return max(abs(x - y) for x, y in zip(a, b))


def command_items(system, since_t, until_t=math.inf):
    return [(t, msg['command']) for t, msg in system.commands.since(since_t) if t <= until_t]


def assert_commands_safe(items):
    """Every JointCommand is in the joint limits, and consecutive ones never move a joint faster
    than its velocity limit allows (over the time between their receptions, plus jitter)."""
    assert len(items) > 50
    for (t0, a), (t1, b) in zip([(None, None)] + items[:-1], items):
        for angle, limit in zip(b, LIMITS):
            assert limit.lower <= angle <= limit.upper, (angle, limit)
        if a is None:
            continue
        dt = max(t1 - t0, 0.0) + RECEPTION_JITTER_S
        for x, y, limit in zip(a, b, LIMITS):
            assert abs(x - y) <= limit.velocity * dt + 1e-6, (
                'joint %s moved %.4f rad in %.3f s (limit %.2f rad/s)'
                % (limit.name, abs(x - y), t1 - t0, limit.velocity))


def interpolate(series, t):
    """Return the value of a series [(t, values)] at time t (linear between its points)."""
    times = [s[0] for s in series]
    i = bisect.bisect_right(times, t)
    if i <= 0 or i >= len(series):
        return series[min(max(i - 1, 0), len(series) - 1)][1]
    (t0, a), (t1, b) = series[i - 1], series[i]
    w = (t - t0) / (t1 - t0) if t1 > t0 else 1.0
    return [x + w * (y - x) for x, y in zip(a, b)]


@pytest.fixture(scope='module')
def system(shared_bed):
    return System(shared_bed)


@pytest.fixture
def teleop(system):
    """A calibrated puppet at POSE, Baxter's right arm not following, a clean link."""
    system.rb.reset_link()
    if not hasattr(system, 'calibrated'):
        system.wait(lambda: system.robot_state() == interface.CALIBRATING, 90,
                    'arm_R calibrating with Baxter enabled')
        system.do('calibrate', pose=POSE)
        system.calibrated = True
    system.stop_following()
    system.do('hand', pose=POSE)
    yield system
    system.rb.reset_link()
    system.stop_following()


# 50 +- 10 ms one way (round trips of about 0.1 s, so arm_X counts every sample some 0.05 s
# older than it is), and 1 % loss on a shorter link. Not here: 50 ms with 1 % loss at the
# firmware's 10 Hz. TCP recovers a lost sample of so thin a stream only after 0.3-0.45 s (the
# next sample's SACK or a tail-loss probe, then the retransmission's trip), more than the 0.4 s
# state timeout, so arm_R stops Baxter every few seconds there (docs/remote.md, figures).
@pytest.mark.parametrize('delay_ms, jitter_ms, loss', [(50, 10, 0.0), (20, 4, 0.01)])
def test_follows_over_a_delayed_lossy_link_within_limits(teleop, delay_ms, jitter_ms, loss):
    s = teleop
    s.rb.bed.set(delay_ms=delay_ms, jitter_ms=jitter_ms, loss=loss)
    s.follow()
    s.wait(lambda: s.baxter_on(s.puppet_angles()), 30,
           "Baxter's right arm on the puppet pose")
    start_t = time.time()
    # A hand trajectory: joints s0 and e1 swing 0.25 rad, at most 0.52 rad/s (under the approach
    # and velocity limits, so Baxter can keep up with it).
    s.do('sine', pose=POSE, joints=[0, 3], amplitude_rad=0.25, period_s=3.0, duration_s=6.0)
    end_t = time.time()
    s.wait(lambda: s.baxter_on(s.puppet_angles()), 30,
           "Baxter's right arm back on the puppet pose")
    status = s.rb.bed.status()['links']
    assert (status['to-robot']['lost'] > 0) == (loss > 0), status['to-robot']

    # Baxter tracked the puppet: at every measurement during the trajectory, its pose is the
    # puppet's pose (as serial_R published it on the operator host) of some 0.02-0.5 s earlier
    # (the one-way delay and jitter, a state period of 100 ms, Baxter's command and motion lag),
    # and it moved with the swing.
    puppet = [(t, m['position']) for t, m in s.puppet.since(start_t - 1.0) if t <= end_t]
    measured = [m for m in s.baxter_arm(start_t + 1.0) if m[0] <= end_t]
    assert len(measured) > 100 and len(puppet) > 30
    lags = [i * 0.01 for i in range(2, 51)]
    worst = 0.0
    for t, pose in measured:
        worst = max(worst, min(max_error(pose, interpolate(puppet, t - lag)) for lag in lags))
    assert worst < 0.03, 'Baxter off the delayed hand trajectory by %.3f rad' % worst
    swing = max(m[1][0] for m in measured) - min(m[1][0] for m in measured)
    assert swing > 0.4, 'Baxter did not follow the swing (s0 moved %.3f rad)' % swing
    assert s.robot_state() == interface.FOLLOWING
    assert_commands_safe(command_items(s, start_t - 5.0))


def test_cut_stops_baxter_and_restore_needs_a_new_press(teleop):
    s = teleop
    s.rb.bed.set(delay_ms=20, jitter_ms=5)
    s.follow()
    s.wait(lambda: s.baxter_on(s.puppet_angles()), 30,
           "Baxter's right arm on the puppet pose")
    moved = list(POSE)
    moved[0] += 0.2
    s.do('hand', pose=moved)
    time.sleep(1.0)
    # Cut while the hand moves back: arm_R's target changes until the cut.
    s.do('hand', pose=POSE)
    time.sleep(0.15)
    s.rb.bed.cut()
    cut_t = time.time()
    s.wait(lambda: s.robot_state() == interface.FAULT, 10, 'teleop FAULT on the robot host')
    far = list(POSE)
    far[0] -= 0.25
    s.do('hand', pose=far)  # the puppet moves on during the cut: a new target for later
    time.sleep(3.0)
    items = command_items(s, cut_t - 2.0)
    changes = [t for (t0, a), (t, b) in zip(items, items[1:]) if max_error(a, b) > 1e-9]
    assert changes and changes[0] < cut_t, 'Baxter was not being commanded before the cut'
    assert changes[-1] - cut_t < interface.STOP_WITHIN_S, (
        'a command moving Baxter came %.3f s after the cut' % (changes[-1] - cut_t))
    # What comes after is the stay command: Baxter's measured pose, and Baxter stays there.
    late = command_items(s, cut_t + interface.STOP_WITHIN_S)
    held = s.baxter_arm(time.time() - 0.5)[-1][1]
    for _, command in late:
        assert max_error(command, held) < 0.01
    detail = s.robot_teleop.last()['detail']
    assert 'joint states' in detail, detail

    # Restore: fresh data again, but nothing moves until a new press.
    s.rb.bed.restore()
    restore_t = time.time()
    s.wait(lambda: s.puppet_angles() and s.robot_teleop.since(restore_t), 10,
           'teleop_state after the restore')
    time.sleep(3.0)
    quiet = s.baxter_arm(restore_t)
    assert max(max_error(pose, held) for _, pose in quiet) < 0.005, 'Baxter moved unpressed'
    assert all(msg['state'] != interface.FOLLOWING for _, msg in s.robot_teleop.since(restore_t))
    assert all(max_error(c, held) < 0.01 for _, c in command_items(s, restore_t))

    # The press: a slow approach (at most ~approach_speed) to the puppet, then on it.
    target = s.puppet_angles()
    assert max_error(held, target) > 0.1, 'nothing to approach: the test moved too little'
    press_t = time.time()
    s.follow()
    s.wait(lambda: s.baxter_on(target), 30,
           "Baxter's right arm on the puppet pose after the press")
    approach = command_items(s, press_t)
    for (t0, a), (t1, b) in zip(approach, approach[1:]):
        speed = max_error(a, b) / (max(t1 - t0, 0.0) + RECEPTION_JITTER_S)
        assert speed <= APPROACH_SPEED_RAD_S * 1.05, 'approach at %.2f rad/s' % speed
    first = approach[0][1]
    assert max_error(first, held) < 0.05, 'the first command after the press jumped'


def test_growing_delay_stops_following_with_the_reason_on_both_hosts(teleop):
    # The delay grows within a few seconds, from a link where arm_R follows: arm_R's clock
    # estimate keeps the short round trips of the last 5 s (link_clock.CLOCK_WINDOW), so the
    # sample age is what tells (arm_R counts half the shortest round trip on top of it).
    s = teleop
    s.rb.bed.set(delay_ms=10)
    s.follow()
    start_t = time.time()
    for delay_ms in (150, 250):
        s.rb.bed.set(delay_ms=delay_ms)
        time.sleep(1.0)
        assert s.robot_state() == interface.FOLLOWING, (
            'stopped at %d ms one way (under the %.2f s bound): %s'
            % (delay_ms, MAX_SAMPLE_AGE_S, s.robot_teleop.last()))
    s.rb.bed.set(delay_ms=400)
    over_t = time.time()
    s.wait(lambda: s.robot_state() == interface.FAULT, 10, 'teleop FAULT on the robot host')
    fault_t = time.time()
    assert fault_t - over_t < 2.0
    detail = s.robot_teleop.last()['detail']
    assert 'old' in detail and '%.2f s bound' % MAX_SAMPLE_AGE_S in detail, detail
    # The operator host (what the GUI shows) gets the FAULT and a link_state naming the network.
    s.wait(lambda: any(m['state'] == interface.FAULT for _, m in s.op_teleop.since(start_t)), 10,
           'teleop_state FAULT on the operator host')
    link = s.wait(lambda: [m for _, m in s.op_link.since(over_t)
                           if m['fault'] == 'network' and m['sample_age'] > MAX_SAMPLE_AGE_S],
                  10, "link_state with fault 'network' and the sample age over the bound on the "
                  'operator host')[-1]
    assert link['level'] == 2, link   # ERROR: Baxter cannot follow
    assert link['max_sample_age'] == pytest.approx(MAX_SAMPLE_AGE_S)
    op_detail = [m for _, m in s.op_teleop.since(start_t) if m['state'] == interface.FAULT][-1]
    assert 'bound' in op_detail['detail'], op_detail
