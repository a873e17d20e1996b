"""RoboPuppet's ROS interface in one table: names, enumerations and timing every node shares.

Nodes, the GUI, tests and benchmarks take topic and service names, opmodes, encoder statuses,
teleop states and the puppet's timing from here, so that each fact has one place. Pure: no rospy.
Baxter's own topics are Rethink's (baxter_core_msgs); the puppet's are the 2020 design's.
"""

# ---- sides ----------------------------------------------------------------------------------
PUPPET_SIDES = ('L', 'R')           # a puppet arm: /puppet/arm_L, /puppet/arm_R
BAXTER_SIDES = ('left', 'right')    # Baxter's arms, as its topics name them
BAXTER_SIDE = {'L': 'left', 'R': 'right'}  # the Baxter arm that copies a puppet arm


def check_side(side):
    """Return a puppet side unchanged.

    Raises:
        ValueError: side is not 'L' or 'R'.
    """
    if side not in PUPPET_SIDES:
        raise ValueError("arm side must be 'L' or 'R', got %r" % (side,))
    return side


# ---- the puppet arm's topics and services, under puppet_ns(side) ------------------------------
def puppet_ns(side):
    """Return the ROS namespace of a puppet arm, e.g. '/puppet/arm_R' (ValueError: bad side)."""
    return '/puppet/arm_%s' % check_side(side)


def node_param(node, side, name):
    """Return a private parameter of one arm's node as the launch files name it, e.g.
    node_param('arm', 'R', 'comm_rate') -> '/arm_R/comm_rate'."""
    return '/%s_%s/%s' % (node, check_side(side), name)


def ini_file_name(side):
    """Return the default ini file of one puppet arm (config_X's ~file_name), e.g. 'arm_R.ini'."""
    return 'arm_%s.ini' % check_side(side)


def sim_ns(side):
    """Return the namespace of a simulated puppet's operator topics, e.g. '/puppet_sim/arm_R'."""
    return '/puppet_sim/arm_%s' % check_side(side)


def joint_topic(side, joint, name):
    """Return a per-joint topic, e.g. joint_topic('R', 3, 'enc_stat') ->
    '/puppet/arm_R/joint_3/enc_stat' (name: a setting, enc_stat, angle, voltage or setpoint)."""
    return '%s/joint_%d/%s' % (puppet_ns(side), joint, name)


def gripper_topic(side, gripper):
    """Return a gripper reading's topic, e.g. '/puppet/arm_R/gripper_3'."""
    return '%s/gripper_%d' % (puppet_ns(side), gripper)


# Relative to puppet_ns(side):
JOINT_STATES = 'joint_states'       # sensor_msgs/JointState: position rad, effort V (serial_X)
USER_BUTTON = 'user_btn'            # std_msgs/UInt8, 0 none or 1..4 (serial_X)
HEARTBEAT = 'heartbeat'             # std_msgs/Empty, one per firmware heartbeat (serial_X)
OPMODE = 'opmode'                   # std_msgs/String, limp, hold or feel (to serial_X)
TELEOP_STATE = 'teleop_state'       # robopuppet_msgs/TeleopState, latched (arm_X)
GET_CONFIG = 'get_config'           # robopuppet_msgs/GetConfig (config_X)
SET_CONFIG = 'set_config'           # robopuppet_msgs/SetConfig (config_X)
SET_ARM_CONFIG = 'set_arm_config'   # robopuppet_msgs/SetArmConfig, several joints (config_X)
STORED_SETTINGS = 'stored_settings'  # robopuppet_msgs/ArmSettings, latched (config_X)
# robopuppet_msgs/ArmSettings, latched (config_X): what the device should hold now, the stored
# settings or, in feel mode, those with feel mode's gentle gains (profile 'feel'; serial_X)
ACTIVE_SETTINGS = 'active_settings'
FEEL_PROFILE = 'feel'   # ArmSettings.profile of feel mode's settings ('': as stored)
LINK_PING = 'link_ping'             # robopuppet_msgs/LinkPing from the robot host (arm_X)
LINK_ECHO = 'link_echo'             # robopuppet_msgs/LinkPing answered by the operator host
LINK_STATE = 'link_state'           # robopuppet_msgs/LinkState (arm_X)
# sensor_msgs/JointState: the pose the calibration awaits (the wizard's or calibrate's), shown
# by the ghost
CALIBRATION_TARGET = 'calibration_target'
# Relative to sim_ns(side): the simulated puppet's operator topics (puppet_sim_X), and what it
# shows of the device for tests and the GUI.
SIM_HAND, SIM_BUTTON, SIM_GRIPPERS, SIM_CONTROL = 'hand', 'button', 'grippers', 'control'
SIM_HAND_TORQUE = 'hand_torque'  # sensor_msgs/JointState: effort = the hand's torque N m
SIM_LINE_NOISE = 'line_noise'
SIM_DEVICE_CONFIG, SIM_DEVICE_OPMODE = 'device_config', 'device_opmode'
DIAGNOSTICS = '/diagnostics'
# The assist (robopuppet.assist): one Baxter arm predicted from the other's motion.
ASSIST_TARGET = 'assist_target'  # robopuppet_msgs/AssistTarget, relative to the leader's puppet_ns
# sensor_msgs/JointState, relative to puppet_ns of the follower arm's side: the predicted pose
# (Baxter's joint names), shown by the assist's ghost
ASSIST_PREDICTION = 'assist_prediction'
ASSIST_STATE = '/puppet/assist_state'      # robopuppet_msgs/AssistState, latched (assist)
ASSIST_COMMAND = '/puppet/assist_command'  # std_msgs/String: 'stop' or 'start' (the GUI's)
ASSIST_COMMANDS = ('stop', 'start')
# The user-study kit (robopuppet.study): other input devices in the puppet's place, tasks, trials.
STUDY_DEVICES = ('puppet', 'keyboard', 'gamepad', 'spacemouse', 'marker')
STUDY_TASKS = ('reach_hold', 'trace', 'pick_place', 'bimanual')
STUDY_STATE = '/puppet/study/state'    # robopuppet_msgs/StudyState, latched (study)
STUDY_START = '/puppet/study/start'    # robopuppet_msgs/StudyStart (study; the GUI's Start, Stop)
# robopuppet_msgs/Questionnaire: NASA-TLX and SUS answers after a device (the GUI's, to study)
STUDY_QUESTIONNAIRE = '/puppet/study/questionnaire'
STUDY_MARKERS = '/robopuppet/study_task'  # visualization_msgs/MarkerArray, latched (study)


def marker_server(side):
    """Return the namespace of a side's interactive-marker device, e.g. '/puppet/marker_R'
    (RViz's InteractiveMarkers display: its update topic <ns>/update; feedback on <ns>/feedback)."""
    return '/puppet/marker_%s' % check_side(side)


REPLAY_STOP = '/puppet/replay_stop'  # std_msgs/Empty: stop a running replay (the GUI's Stop)
RECORD_SERVICE = '/puppet/record'        # robopuppet_msgs/Record: start or stop an episode
RECORDING_TOPIC = '/puppet/recording'    # robopuppet_msgs/RecordingState, latched (recorder)
# visualization_msgs/MarkerArray, latched (arm_X): the keep-out zones, in Baxter's base frame
ZONE_MARKERS = '/robopuppet/keepout_zones'
# visualization_msgs/MarkerArray, latched (each arm_X, in a namespace of its own): the zones
# holding Baxter's arms back, drawn over in a strong colour
ZONE_HOLD_MARKERS = '/robopuppet/keepout_zones_holding'
# visualization_msgs/MarkerArray, latched (sim_cameras): the room the simulated cameras draw (bed,
# patient), muted, in Baxter's base frame
ROOM_MARKERS = '/robopuppet/room'
# Each node's status of one arm on /diagnostics: hardware_id is puppet_ns(side) and the status
# name ends with what it is about, so a reader finds it without knowing the node's name.
DIAG_LINK = 'puppet serial link'   # serial_X
DIAG_TELEOP = 'teleoperation'      # arm_X
DIAG_NETWORK = 'operator-robot link'  # arm_X: the link between the two hosts

# ---- Baxter's own API (Rethink's names: the real robot's, served by baxter_sim too) -----------
ROBOT_STATE = '/robot/state'
ROBOT_JOINT_STATES = '/robot/joint_states'
JOINT_STATE_PUBLISH_RATE = '/robot/joint_state_publish_rate'   # std_msgs/UInt16, Hz
SET_SUPER_ENABLE = '/robot/set_super_enable'
SET_SUPER_RESET = '/robot/set_super_reset'
SET_SUPER_STOP = '/robot/set_super_stop'
SOFTWARE_VERSION_PARAM = '/rethink/software_version'
ROBOT_DESCRIPTION_PARAM = '/robot_description'   # the URDF text (robot_state_publisher's)
DIGITAL_IO_COMMAND = '/robot/digital_io/command'    # baxter_core_msgs/DigitalOutputCommand
ANALOG_IO_COMMAND = '/robot/analog_io/command'      # baxter_core_msgs/AnalogOutputCommand
HEAD_PAN_COMMAND = '/robot/head/command_head_pan'   # baxter_core_msgs/HeadPanCommand
HEAD_NOD_COMMAND = '/robot/head/command_head_nod'   # std_msgs/Bool
HEAD_STATE = '/robot/head/head_state'               # baxter_core_msgs/HeadState
# The stand-in's own input (not Baxter's): press a cuff or button (DigitalOutputCommand).
SIM_DIGITAL_INPUT = '/baxter_sim/digital_input'


def digital_io_state_topic(name):
    """Return the state topic of a digital IO component, e.g. 'left_lower_cuff'."""
    return '/robot/digital_io/%s/state' % name


def navigator_state_topic(location):
    """Return the state topic of a navigator ('left', 'right', 'torso_left', 'torso_right')."""
    return '/robot/navigators/%s_navigator/state' % location


def analog_io_state_topic(name):
    """Return the state topic of an analog IO component, e.g. 'left_hand_range'."""
    return '/robot/analog_io/%s/state' % name


def ik_service(side):
    """Return the name of a Baxter side's IK service (baxter_core_msgs/SolvePositionIK)."""
    return '/ExternalTools/%s/PositionKinematicsNode/IKService' % side


def sim_link_prefix(master_uri, ros_home):
    """Return the default path prefix of the simulated puppets' pty links, <prefix>_arm_<side>.

    In this user's ROS_HOME and named after the ROS master, so that two systems on two masters
    never share a link. arm.launch's sim_link_prefix default is the same expression.
    """
    master = master_uri.split('//')[-1].rstrip('/').replace(':', '_').replace('/', '_')
    return '%s/robopuppet/pty_%s' % (ros_home, master)


def limb_topic(side, name):
    """Return a topic of one Baxter arm, e.g. limb_topic('left', 'joint_command')."""
    return '/robot/limb/%s/%s' % (side, name)


def collision_avoidance_state_topic(side):
    """Return a Baxter arm's CollisionAvoidanceState topic."""
    return limb_topic(side, 'collision_avoidance_state')


def suppress_topic(side, behaviour):
    """Return the topic that suppresses an arm's safety behaviour while messages keep coming,
    e.g. suppress_topic('left', 'cuff_interaction')."""
    return limb_topic(side, 'suppress_' + behaviour)


CAMERAS_NS = '/cameras'
CAMERA_IMAGE = 'image'                  # sensor_msgs/Image, raw
CAMERA_COMPRESSED = 'image/compressed'  # sensor_msgs/CompressedImage, JPEG
CAMERA_INFO = 'camera_info'             # sensor_msgs/CameraInfo
# Baxter's camera services (baxter_core_msgs; sim_cameras serves them for Baxter's cameras)
CAMERAS_LIST = '/cameras/list'    # ListCameras: the cameras that have power
CAMERAS_OPEN = '/cameras/open'    # OpenCamera: start streaming at a mode, err 0 when done
CAMERAS_CLOSE = '/cameras/close'  # CloseCamera: stop streaming, err 0 when done


def camera_topic(camera, name):
    """Return a camera's topic, e.g. camera_topic('right_hand_camera', CAMERA_COMPRESSED) ->
    '/cameras/right_hand_camera/image/compressed'."""
    return '%s/%s/%s' % (CAMERAS_NS, camera, name)


def camera_of_topic(topic, name):
    """Return the camera whose `name` topic this is (camera_topic's inverse), or None."""
    prefix, suffix = CAMERAS_NS + '/', '/' + name
    if not (topic.startswith(prefix) and topic.endswith(suffix)):
        return None
    camera = topic[len(prefix):-len(suffix)]
    return camera if camera and '/' not in camera else None


def hand_camera(side):
    """Return the camera on a Baxter arm's hand ('left' or 'right'), e.g. 'left_hand_camera'."""
    return '%s_hand_camera' % side


# Baxter's own cameras (Rethink's names) and the room camera a lab adds; the stand-in renders
# all of them, Baxter's on its hand-camera frames of the URDF.
BAXTER_CAMERAS = ('head_camera', 'left_hand_camera', 'right_hand_camera')
ROOM_CAMERA = 'room_camera'
# The cameras the simulated system renders (sim_cameras' ~cameras default; a real Baxter streams
# at most two of its three) and so those an episode records by default (the recorder's ~cameras).
SIM_CAMERAS = (ROOM_CAMERA, 'left_hand_camera', 'right_hand_camera')


def baxter_gripper_topic(side, name):
    """Return a topic of one Baxter gripper, e.g. '/robot/end_effector/left_gripper/state'."""
    return '/robot/end_effector/%s_gripper/%s' % (side, name)


# ---- puppet enumerations (the wire codes index these tuples) ----------------------------------
DEVICE_OPMODES = ('limp', 'hold')   # the firmware's two; the wire codes index these
# feel: the device holds (gentle gains, setpoints streamed from Baxter's pose; docs/feel.md)
OPMODES = DEVICE_OPMODES + ('feel',)
LIMP, HOLD, FEEL = OPMODES
ENC_STATUS = ('Working', 'Disconnected', 'Uncalibrated')
WORKING, DISCONNECTED, UNCALIBRATED = ENC_STATUS
NUM_GRIPPERS = 4
END_PIECE_GRIPPER = 3  # the pencil end piece's button: reads ~1 released, ~0 pressed
NUM_BUTTONS = 4
# what arm_X does with buttons 1..3: 1 cycles the opmode limp -> hold -> feel -> limp
BUTTON_OPMODE, BUTTON_LEFT, BUTTON_RIGHT = 1, 2, 3
BUTTON_RECORD = 4   # the recorder's: starts and stops an episode

# ---- teleop states (robopuppet_msgs/TeleopState's constants) ----------------------------------
TELEOP_STATES = ('no_robot', 'calibrating', 'ready', 'following', 'fault')
NO_ROBOT, CALIBRATING, READY, FOLLOWING, FAULT = TELEOP_STATES

# ---- timing ---------------------------------------------------------------------------------
HEARTBEAT_PERIOD_S = 1.0     # the 2020 firmware sends a heartbeat every second
HEARTBEAT_TIMEOUT_S = 2.5    # no heartbeat for this long: the puppet counts as silent
DEFAULT_COMM_RATE_HZ = 10.0  # the 2020 firmware's state-set rate (a compile-time constant)
STOP_WITHIN_S = 0.5          # a silent puppet stops Baxter following within this time
