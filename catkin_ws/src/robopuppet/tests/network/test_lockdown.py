"""docs/remote.md, "Locking the link down": with config/nftables/robopuppet.nft loaded on both
hosts, a third host on the link (the intruder) reaches neither the ROS master, nor a
subscriber's node port, nor a service on the operator host, while the peer host still reaches
all three.

The same three attacks are first made without the rule set and must succeed there: so the test
shows that they are real attacks, and that the rule set (not a broken bed) stops them. The
service is the real config node (`rosrun robopuppet config _arm_side:=R`); the subscriber is a
rospy node on Baxter's joint command topic. Needs root and nft (skipped otherwise).
"""
import shutil
import time
import urllib.parse

import pytest
from baxter_core_msgs.msg import JointCommand
from robopuppet import interface
from robopuppet_msgs.srv import GetConfig, GetConfigRequest

from netbed_testing import HELPERS
from ros_probes import FakePublisher, call_service, tcp_connects, xmlrpc_call

NODE = str(HELPERS / 'ros_node.py')
TOPIC = interface.limb_topic('left', 'joint_command')
SERVICE = '%s/%s' % (interface.puppet_ns('R'), interface.GET_CONFIG)
BLOCKED_TIMEOUT_S = 1.5  # a dropped SYN never answers: give up after this


def reaches_master(rb, host):
    try:
        code, _, _ = rb.call_in(host, xmlrpc_call, rb.master_uri, 'getSystemState', '/probe',
                                timeout_s=BLOCKED_TIMEOUT_S)
        return code == 1
    except OSError:
        return False


def calls_service(rb, host, service_uri):
    try:
        response = rb.call_in(host, call_service, service_uri, SERVICE, GetConfig,
                              GetConfigRequest(joint=2), timeout_s=BLOCKED_TIMEOUT_S)
    except OSError:
        return False
    return response.angle_min < response.angle_max  # the joint's real settings came back


def feeds_subscriber(rb, host, subscriber, tag):
    """Publish a JointCommand named `tag` to the subscriber without the master; return True
    when the subscriber printed it."""
    publisher = rb.call_in(host, FakePublisher, rb.address(host), TOPIC, JointCommand)
    try:
        rb.call_in(host, publisher.announce, subscriber['uri'], timeout_s=BLOCKED_TIMEOUT_S)
        if not publisher.wait_connected(10.0):
            return False
        deadline = time.monotonic() + 10.0
        while time.monotonic() < deadline:
            publisher.publish(JointCommand(mode=JointCommand.POSITION_MODE, command=[0.0],
                                           names=[tag]))
            if any(line.get('msg', {}).get('names') == [tag] for line in subscriber['proc']
                   .json_lines()):
                return True
            time.sleep(0.1)
        return False
    except OSError:
        return False
    finally:
        publisher.close()


def test_only_the_peer_reaches_the_master_the_nodes_and_the_services(ros_bed):
    if shutil.which('nft') is None:
        pytest.skip('nft missing: install the Debian package nftables (tools/setup.sh does)')
    rb = ros_bed
    rb.roscore()
    listener = rb.python('robot', NODE, 'listen', TOPIC, 'baxter_core_msgs/JointCommand')
    rb.rosrun('operator', 'robopuppet', 'config', '_arm_side:=R')
    subscriber = {'proc': listener, 'uri': listener.wait_for(
        lambda p: p.json_lines() and p.json_lines()[0]['uri'], 30, 'the subscriber ready')}
    rb.wait_registered('robot', 2, SERVICE)
    service_uri = rb.master_call('robot', 'lookupService', SERVICE)
    master_port = urllib.parse.urlparse(rb.master_uri).port

    # Without the rule set, the intruder does all three.
    assert reaches_master(rb, 'intruder')
    assert feeds_subscriber(rb, 'intruder', subscriber, 'intruder, link open')
    assert calls_service(rb, 'intruder', service_uri)

    rb.lock_down()
    assert not reaches_master(rb, 'intruder')
    assert not rb.call_in('intruder', tcp_connects, rb.address('robot'), master_port,
                          BLOCKED_TIMEOUT_S)
    assert not feeds_subscriber(rb, 'intruder', subscriber, 'intruder, link locked')
    assert not calls_service(rb, 'intruder', service_uri)
    # The peers still do, and so does the robot host itself (loopback stays open).
    assert reaches_master(rb, 'operator')
    assert reaches_master(rb, 'robot')
    assert feeds_subscriber(rb, 'operator', subscriber, 'operator, link locked')
    assert calls_service(rb, 'robot', service_uri)
    names = [line['msg']['names'] for line in listener.json_lines() if 'msg' in line]
    assert ['intruder, link locked'] not in names
