"""Unit tests of input.launch and arm.launch's device: what feeds one arm's puppet topics."""
import os

import pytest

from test_launch_files import LAUNCH_DIR, load

INPUT = os.path.join(LAUNCH_DIR, 'input.launch')
EVENT_DEVICES = ('keyboard', 'gamepad', 'spacemouse')


def test_arm_launch_runs_the_puppet_by_default_with_the_simulated_link_in_one_place():
    nodes, params = load('arm_side:=R', 'sim_puppet:=true', 'sim_link_prefix:=/tmp/p')
    assert {'config_R', 'serial_R', 'puppet_sim_R', 'arm_R'} <= set(nodes)
    assert 'input_R' not in nodes
    assert params['/serial_R/port_name'] == params['/puppet_sim_R/port_link'] == '/tmp/p_arm_R'
    _, params = load('arm_side:=R', 'sim_puppet:=true', 'sim_link:=/tmp/mine')
    assert params['/serial_R/port_name'] == params['/puppet_sim_R/port_link'] == '/tmp/mine'
    _, params = load('arm_side:=L')
    assert params['/serial_L/port_name'] == '/dev/ttyACM0'


@pytest.mark.parametrize('device', EVENT_DEVICES + ('marker',))
def test_a_study_device_stands_in_serial_xs_place(device):
    nodes, params = load('arm_side:=R', 'device:=' + device, 'events:=/tmp/ev_R',
                         'sim_puppet:=true')
    assert 'serial_R' not in nodes and 'puppet_sim_R' not in nodes
    assert {'config_R', 'arm_R', 'input_R'} <= set(nodes)
    assert nodes['input_R'].type == 'input_device'
    assert (params['/input_R/arm_side'], params['/input_R/device'],
            params['/input_R/events']) == ('R', device, '/tmp/ev_R')


def test_device_none_leaves_the_slot_empty_and_input_launch_runs_alone():
    nodes, _ = load('arm_side:=R', 'device:=none')
    assert {'config_R', 'arm_R'} <= set(nodes) and not {'serial_R', 'input_R'} & set(nodes)
    nodes, params = load('device:=gamepad', 'arm_side:=L', 'events:=/dev/input/event3',
                         launch=INPUT)
    assert set(nodes) == {'input_L'} and params['/input_L/events'] == '/dev/input/event3'
    nodes, _ = load('arm_side:=L', launch=INPUT)
    assert set(nodes) == {'serial_L'}


def test_an_unknown_device_is_refused():
    with pytest.raises(Exception, match='trackball'):
        load('device:=trackball', launch=INPUT)


def test_main_sim_passes_the_device_on_to_its_arm():
    nodes, _ = load('device:=marker', 'gui:=false', 'rviz:=false',
                    launch=os.path.join(LAUNCH_DIR, 'main_sim.launch'))
    assert 'input_R' in nodes and 'serial_R' not in nodes and 'puppet_sim_R' not in nodes
