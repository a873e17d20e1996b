"""ROS 1 across the bed: the master on the robot host, nodes on both hosts, a faulty link.

Needs root (skipped otherwise) and ROS (`. tools/env.sh`). Run: tools/run_tests.py network.
"""
from robopuppet import interface

from netbed_testing import HELPERS

NODE = str(HELPERS / 'ros_node.py')


def received_numbers(proc):
    return [int(line['msg']['data']) for line in proc.json_lines() if 'msg' in line]


def test_talker_on_operator_reaches_listener_on_robot_over_a_faulty_link(master_bed):
    master_bed.bed.set(delay_ms=20, jitter_ms=5, loss=0.03)
    listener = master_bed.python('robot', NODE, 'listen', '/chatter', 'std_msgs/String')
    talker = master_bed.python('operator', NODE, 'talk', '/chatter', '50')
    numbers = listener.wait_for(lambda p: len(received_numbers(p)) >= 60 and received_numbers(p),
                                45, '60 messages from the talker')
    # TCP carries ROS over the losses: every message in order, none missing after the first.
    assert numbers == list(range(numbers[0], numbers[0] + len(numbers)))
    links = master_bed.bed.status()['links']
    assert links['to-robot']['lost'] > 0 and links['to-operator']['lost'] > 0
    # The registrations crossed the link too: each node is known by its host's address.
    publishers = master_bed.wait_registered('robot', 0, '/chatter')
    talker_node = talker.json_lines()[0]
    assert publishers == [talker_node['node']]
    assert master_bed.address('operator') in talker_node['uri']
    assert master_bed.address('robot') in listener.json_lines()[0]['uri']


def test_roslaunch_of_each_host_across_the_link(master_bed):
    master_bed.bed.set(delay_ms=5, jitter_ms=1)
    master_bed.roslaunch('robot', 'robot.launch', 'run_side_L:=false')
    master_bed.roslaunch('operator', 'operator.launch', 'run_side_L:=false', 'sim_puppet:=true',
                      'gui:=false', 'rviz:=false',
                      'sim_link_prefix:=%s/pty' % master_bed.work_dir)
    # The robot's joint states reach the operator host, the puppet's reach the robot host.
    robot_states = master_bed.python('operator', NODE, 'listen', interface.ROBOT_JOINT_STATES,
                                  'sensor_msgs/JointState')
    puppet_states = master_bed.python(
        'robot', NODE, 'listen', '%s/%s' % (interface.puppet_ns('R'), interface.JOINT_STATES),
        'sensor_msgs/JointState')
    for proc, what in ((robot_states, "Baxter's joint states"),
                       (puppet_states, "the puppet's joint states")):
        msgs = proc.wait_for(lambda p: len(p.json_lines()) > 5 and p.json_lines()[1:], 60, what)
        assert msgs[-1]['msg']['name'] and len(msgs[-1]['msg']['position']) == len(
            msgs[-1]['msg']['name'])
    assert 'right_s0' in robot_states.json_lines()[-1]['msg']['name']
    # The operator's config service is registered from the operator's address.
    service = '%s/%s' % (interface.puppet_ns('R'), interface.GET_CONFIG)
    master_bed.wait_registered('robot', 2, service)
    uri = master_bed.master_call('robot', 'lookupService', service)
    assert uri.startswith('rosrpc://%s:' % master_bed.address('operator'))
