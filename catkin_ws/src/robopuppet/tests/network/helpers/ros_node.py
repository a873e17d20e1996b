#!/usr/bin/python3
"""A small rospy node for the network tests, run in a bed namespace as a child process (rospy can
init only once per process); it reports on stdout, one JSON object per line.

    ros_node.py talk TOPIC [RATE_HZ]    publish std_msgs/String '0', '1', '2', ... at RATE_HZ
    ros_node.py listen TOPIC TYPE [nodelay] [recover]
                                        subscribe (TYPE e.g. std_msgs/String,
                                        baxter_core_msgs/JointCommand); print each message;
                                        nodelay: ask for TCP_NODELAY, as arm_X does for the
                                        puppet's joint_states (a lost packet then delays the
                                        samples as it does arm_X's); recover: watch TOPIC
                                        with robopuppet.link_recovery, as gui_X does

First line: {"ready": true, "node": NAME, "uri": its XML-RPC URI}. Then, for `listen`, one line
per message: {"t": receipt time (s, time.time()), "msg": {field: value, ...}}. Environment:
ROS_MASTER_URI and ROS_IP, as the harness sets them.
"""
import json
import sys
import time

import roslib.message
import rospy
from std_msgs.msg import String

from robopuppet.link_recovery import LinkRecovery


def to_plain(msg):
    """Return a message's fields as JSON-ready values (flat messages and arrays)."""
    out = {}
    for slot in msg.__slots__:
        value = getattr(msg, slot)
        if hasattr(value, '__slots__'):
            value = to_plain(value)
        elif isinstance(value, (tuple, list)):
            value = list(value)
        elif isinstance(value, bytes):
            value = list(value)
        elif not isinstance(value, (int, float, str, bool)):
            value = str(value)
        out[slot] = value
    return out


def report(**fields):
    print(json.dumps(fields), flush=True)


def main(argv):
    if len(argv) < 2 or argv[0] not in ('talk', 'listen'):
        print(__doc__, file=sys.stderr)
        return 2
    mode, topic = argv[0], argv[1]
    rospy.init_node('%s_%d' % (mode, int(time.time() * 1e3) % 100000), anonymous=True,
                    disable_signals=False)
    if mode == 'talk':
        rate_hz = float(argv[2]) if len(argv) > 2 else 20.0
        pub = rospy.Publisher(topic, String, queue_size=100)
        report(ready=True, node=rospy.get_name(), uri=rospy.get_node_uri())
        rate = rospy.Rate(rate_hz)
        count = 0
        while not rospy.is_shutdown():
            pub.publish(String(data=str(count)))
            count += 1
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                break
    else:
        msg_class = roslib.message.get_message_class(argv[2])
        if msg_class is None:
            print('unknown message type %s' % argv[2], file=sys.stderr)
            return 2
        rospy.Subscriber(topic, msg_class,
                         lambda msg: report(t=time.time(), msg=to_plain(msg)), queue_size=1000,
                         tcp_nodelay='nodelay' in argv[3:])
        if 'recover' in argv[3:]:
            LinkRecovery(rospy.get_name(), [topic]).start()
        report(ready=True, node=rospy.get_name(), uri=rospy.get_node_uri())
        rospy.spin()
    return 0


if __name__ == '__main__':
    sys.exit(main(rospy.myargv(sys.argv)[1:]))
