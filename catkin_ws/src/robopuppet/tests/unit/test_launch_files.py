"""Unit tests of the launch files: arguments, and how arm.launch wires the nodes of one arm."""
import os
import sys
import xml.etree.ElementTree as ET

import pytest
import roslaunch.config

LAUNCH = os.path.join(os.path.dirname(__file__), '..', '..', 'launch', 'arm.launch')
LAUNCH_DIR = os.path.dirname(LAUNCH)
# The seed's Table 5 defaults, but frame_rate: 30 Hz (pyqtgraph) where the 2020 Tk GUI used 8.
TABLE_5 = {'arm_side': 'L', 'port_name': '/dev/ttyACM0', 'comm_rate': '10.0',
           'frame_rate': '30.0', 'debug_mode': 'true'}


def load(*args, launch=LAUNCH):
    """Return {node name: node} and the params of a launch file run with the given arguments."""
    saved = sys.argv
    sys.argv = ['roslaunch', 'robopuppet', os.path.basename(launch)] + list(args)
    try:
        config = roslaunch.config.load_config_default([launch], None)
    finally:
        sys.argv = saved
    return {n.name: n for n in config.nodes}, {k: p.value for k, p in config.params.items()}


def test_arguments_of_table_5_plus_sim_puppet_and_gui_all_documented():
    args = {a.get('name'): a for a in ET.parse(LAUNCH).getroot().iter('arg')}
    for name, default in dict(TABLE_5, sim_puppet='false', gui='false').items():
        assert args[name].get('default') == default, name
    assert all(a.get('doc') for a in args.values())


@pytest.mark.parametrize('side', ['L', 'R'])
def test_sim_puppet_points_serial_at_the_simulator(side):
    nodes, params = load('arm_side:=' + side, 'sim_puppet:=true', 'comm_rate:=50.0')
    assert {'config_' + side, 'serial_' + side, 'puppet_sim_' + side} <= set(nodes)
    link = '/tmp/robopuppet_arm_' + side
    assert params['/serial_%s/port_name' % side] == link
    assert params['/puppet_sim_%s/port_link' % side] == link
    assert params['/puppet_sim_%s/state_rate' % side] == 50.0
    assert params['/config_%s/file_name' % side] == 'arm_%s.ini' % side
    assert params['/config_%s/seed_file' % side].endswith('/config/arm_%s.ini' % side)


def test_real_puppet_opens_port_name():
    nodes, params = load('port_name:=/dev/ttyUSB3')
    assert {'config_L', 'serial_L'} <= set(nodes)
    assert 'puppet_sim_L' not in nodes
    assert params['/serial_L/port_name'] == '/dev/ttyUSB3'
    assert params['/serial_L/arm_side'] == 'L'


def test_arm_controller_always_and_gui_on_request():
    nodes, _ = load('arm_side:=R')
    assert 'arm_R' in nodes and 'gui_R' not in nodes
    nodes, params = load('arm_side:=R', 'gui:=true', 'sim_puppet:=true', 'frame_rate:=12')
    assert nodes['gui_R'].type == 'gui'
    assert params['/gui_R/frame_rate'] == 12 and params['/gui_R/sim_puppet'] is True
    assert params['/arm_R/arm_side'] == 'R'


@pytest.mark.parametrize('name', ['arm.launch', 'puppet.launch', 'main_sim.launch',
                                  'baxter_sim.launch'])
def test_every_argument_is_documented(name):
    args = ET.parse(os.path.join(LAUNCH_DIR, name)).getroot().findall('arg')
    undocumented = [a.get('name') for a in args if not a.get('doc')]
    assert undocumented == []


def test_main_sim_runs_the_right_arm_on_simulated_hardware_by_default():
    nodes, params = load('rviz:=false', 'gui:=false',
                         launch=os.path.join(LAUNCH_DIR, 'main_sim.launch'))
    assert {'baxter_sim', 'robot_state_publisher', 'config_R', 'serial_R', 'puppet_sim_R',
            'arm_R'} == set(nodes)
    assert params['/serial_R/port_name'] == params['/puppet_sim_R/port_link']


def test_puppet_launch_gives_each_side_its_own_port():
    nodes, params = load('gui:=false', launch=os.path.join(LAUNCH_DIR, 'puppet.launch'))
    assert {'serial_L', 'serial_R', 'arm_L', 'arm_R'} <= set(nodes)
    assert params['/serial_L/port_name'] != params['/serial_R/port_name']
