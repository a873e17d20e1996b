"""baxter_sim's ROS parameters: read, checked, and made into the node's BaxterApi.

A ROS adapter beside baxter_sim_node, whose docstring lists the parameters.
"""
import rospkg
import rospy

from robopuppet import baxter_description as bd, interface, params
from robopuppet.baxter_sim import baxter_api as api
from robopuppet.baxter_sim.baxter_contact import obstacle_contacts
from robopuppet.baxter_sim.baxter_model import BaxterModel


def _param(name, default, check):
    return check(rospy.resolve_name(name), rospy.get_param(name, default))


def contacts(description, urdf_text):
    """Return the arms' ArmContacts with the ~obstacles_file's obstacles: {} when there are
    none, and {} with an error logged when the file cannot be used."""
    try:
        found, text = obstacle_contacts(rospy.get_param('~obstacles_file', None),
                                        rospkg.RosPack().get_path('robopuppet'),
                                        description, urdf_text)
    except ValueError as error:   # also ObstacleFileError and arm_capsules.CapsuleError
        rospy.logerr('baxter_sim: running without obstacles: %s', error)
        return {}
    rospy.loginfo('baxter_sim: %s', text)
    return found


def api_from_params():
    """Return (the BaxterApi the parameters describe, ~rate_hz).

    Raises:
        ValueError: naming an unusable parameter.
        rospkg.ResourceNotFound: no robopuppet package to take the default files from.
    """
    text = rospy.get_param(interface.ROBOT_DESCRIPTION_PARAM, None)
    try:
        if not text:
            with open(bd.urdf_path(rospkg.RosPack().get_path('robopuppet'))) as urdf:
                text = urdf.read()
        description = bd.Description(text)
    except (OSError, bd.DescriptionError) as error:
        raise ValueError('parameter /robot_description: %s' % error) from error
    rate_hz = _param('~rate_hz', 100.0, params.positive)
    timeout_s = _param('~joint_command_timeout', 0.2, params.positive)
    calibrated = _param('~gripper_calibrated', False, api.bool_param)
    model = BaxterModel(description, rospy.get_time(), gripper_calibrated=calibrated,
                        contacts=contacts(description, text))
    return api.BaxterApi(model, timeout_s, loop_rate_hz=rate_hz), rate_hz
