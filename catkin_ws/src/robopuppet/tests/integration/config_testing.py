"""What the config node's rostests share: the fixture, and starting and stopping config_R."""
import os
import time

import roslaunch
import rospkg
import rospy

from robopuppet_msgs.srv import GetConfig

FIXTURE = os.path.join(rospkg.RosPack().get_path('robopuppet'),
                       'tests', 'integration', 'fixtures', 'arm_distinct.ini')
SERVICE = '/puppet/arm_R/get_config'


class ConfigNodeRunner:
    """A unittest.TestCase mixin: start config_R on a file with self.launch, stop it again.

    Sets self.process (the running node or None) and self.log_file (its log file).
    """

    def start_node(self, path, seed=FIXTURE):
        """Start config_R on the live file `path`; return a get_config proxy once it serves."""
        node = roslaunch.core.Node(
            'robopuppet', 'config', name='config_R', output='screen',
            args='_arm_side:=R _file_name:=%s _seed_file:=%s' % (path, seed))
        self.process = self.launch.launch(node)
        self.log_file = [arg.split(':=', 1)[1] for arg in self.process.args
                         if arg.startswith('__log:=')][0]
        rospy.wait_for_service(SERVICE, timeout=20)
        return rospy.ServiceProxy(SERVICE, GetConfig)

    def stop_node(self):
        """Stop config_R and wait until get_config is gone."""
        self.process.stop()
        self.process = None
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            try:
                rospy.wait_for_service(SERVICE, timeout=0.2)
            except rospy.ROSException:
                return
        self.fail('config node did not stop')
