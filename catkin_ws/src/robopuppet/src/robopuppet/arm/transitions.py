"""The teleop states' transition table (robopuppet_msgs/TeleopState's states; README.md,
"Operating the puppet", describes them as the operator sees them). Teleop fires the events."""
from robopuppet.interface import CALIBRATING, FAULT, FOLLOWING, NO_ROBOT, READY

# (state, event) -> next state. Events not listed for a state leave it unchanged.
TRANSITIONS = {
    (NO_ROBOT, 'robot_ok'): CALIBRATING,
    (CALIBRATING, 'robot_lost'): NO_ROBOT,
    (CALIBRATING, 'calibrated'): READY,
    (CALIBRATING, 'silent'): FAULT,
    (READY, 'robot_lost'): NO_ROBOT,
    (READY, 'uncalibrated'): CALIBRATING,
    (READY, 'follow_on'): FOLLOWING,
    (READY, 'silent'): FAULT,
    (FOLLOWING, 'robot_lost'): NO_ROBOT,
    (FOLLOWING, 'uncalibrated'): CALIBRATING,
    (FOLLOWING, 'follow_off'): READY,
    (FOLLOWING, 'silent'): FAULT,
    (FAULT, 'robot_lost'): NO_ROBOT,
    (FAULT, 'fresh'): CALIBRATING,
}
# From any state but these, the arm controller's own failure is a fault.
for _state in (CALIBRATING, READY, FOLLOWING):
    TRANSITIONS[_state, 'controller_failed'] = FAULT
# Following is switched off on entering these states.
STOP_FOLLOWING = (NO_ROBOT, CALIBRATING, READY, FAULT)
