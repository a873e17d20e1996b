"""The robot host's ROS master dies (docs/remote.md, "The robot host's master"): robot.launch,
started without a separate roscore, starts the master itself and stops every node with it.
arm_R must say so to the operator host before it goes: a last teleop_state (fault) naming the
master, soon after the kill, and no traceback on the robot host.

Needs root (skipped otherwise) and ROS (`. tools/env.sh`). Run: tools/run_tests.py network.
"""
import os
import signal
import time

from robopuppet import interface

from netbed_testing import HELPERS

NODE = str(HELPERS / 'ros_node.py')
TOLD_WITHIN_S = 3.0   # roslaunch notices the dead master within a second, then stops arm_R


def test_arm_says_on_the_operator_host_that_the_master_died(ros_bed):
    rb = ros_bed
    port = rb.free_port('robot')
    rb.master_uri = 'http://%s:%d/' % (rb.address('robot'), port)
    launch = rb.start('robot', ['roslaunch', '-p', port, 'robopuppet', 'robot.launch',
                                'run_side_L:=false', 'sim_cameras:=false'], name='robot-launch')
    topic = '%s/%s' % (interface.puppet_ns('R'), interface.TELEOP_STATE)
    launch.wait_for(lambda p: 'arm_R: ' in p.text(), 60, 'arm_R running')
    listener = rb.python('operator', NODE, 'listen', topic, 'robopuppet_msgs/TeleopState')
    listener.wait_for(lambda p: any('msg' in line for line in p.json_lines()), 60,
                      'a teleop_state on the operator host')
    pid = rb.master_call('robot', 'getPid')
    os.kill(pid, signal.SIGKILL)
    kill_t = time.time()

    def told(p):
        return [line for line in p.json_lines()
                if line.get('t', 0.0) > kill_t and line['msg']['state'] == interface.FAULT]
    last = listener.wait_for(told, 20, 'a fault teleop_state after the kill')[0]
    print('told on the operator host %.2f s after the master was killed: %s'
          % (last['t'] - kill_t, last['msg']['detail']))
    assert 'ROS master does not answer' in last['msg']['detail'], last
    assert last['t'] - kill_t < TOLD_WITHIN_S
    launch.wait_for(lambda p: not p.alive() or None, 30, 'roslaunch ending')
    assert 'Traceback' not in launch.text(), launch.tail()
