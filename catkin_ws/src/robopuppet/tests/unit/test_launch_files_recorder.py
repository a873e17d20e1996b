"""Unit tests of recorder.launch's cameras and task arguments (roslaunch config, no ROS master)."""
import os
import sys

import pytest
import roslaunch.config

LAUNCH_DIR = os.path.join(os.path.dirname(__file__), '..', '..', 'launch')


def recorder_params(launch, *args):
    """Return the recorder's parameters {name: value} of a launch file run with args."""
    saved = sys.argv
    sys.argv = ['roslaunch', 'robopuppet', launch, 'gui:=false', 'rviz:=false'] + list(args)
    try:
        config = roslaunch.config.load_config_default([os.path.join(LAUNCH_DIR, launch)], None)
    finally:
        sys.argv = saved
    return {key[len('/recorder/'):]: param.value for key, param in config.params.items()
            if key.startswith('/recorder/')}


@pytest.mark.parametrize('launch', ['recorder.launch', 'operator.launch', 'main_sim.launch'])
def test_the_cameras_recorded_are_the_node_default_unless_a_list_is_given(launch):
    assert 'cameras' not in recorder_params(launch)  # the node's ~cameras default
    assert recorder_params(launch, 'record_cameras:=[right_hand_camera, room_camera]')[
        'cameras'] == ['right_hand_camera', 'room_camera']
    assert recorder_params(launch, 'record_cameras:=[]')['cameras'] == []


@pytest.mark.parametrize('launch', ['recorder.launch', 'operator.launch', 'main_sim.launch'])
def test_the_task_argument_is_the_recorders_task_parameter(launch):
    assert recorder_params(launch)['task'] == ''  # none
    assert recorder_params(launch, 'task:=pick up the cup: 42')['task'] == 'pick up the cup: 42'
    assert recorder_params(launch, 'task:=42')['task'] == '42'  # text, not a number
