#!/usr/bin/python3
"""Stamp Baxter's JointCommands on arrival, for bench_remote.py: run on the robot host (child
process), it subscribes TOPIC (baxter_core_msgs/JointCommand) with tcp_nodelay, as arm_X's own
subscribers do, so that Nagle's algorithm on the publisher's side does not hold commands back,
and prints one JSON object per line: first {"ready": true}, then per command
{"t": time.time() on arrival, "msg": {"command": [rad, ...]}}.

    command_stamps.py TOPIC
"""
import json
import sys
import time

import rospy
from baxter_core_msgs.msg import JointCommand


def main(argv):
    rospy.init_node('command_stamps', anonymous=True)
    rospy.Subscriber(argv[0], JointCommand, lambda msg: print(json.dumps(
        {'t': time.time(), 'msg': {'command': list(msg.command)}}), flush=True),
        queue_size=1000, tcp_nodelay=True)
    print(json.dumps({'ready': True}), flush=True)
    rospy.spin()
    return 0


if __name__ == '__main__':
    sys.exit(main(rospy.myargv(sys.argv)[1:]))
