"""Unit tests of launch/arm.launch: its arguments and how sim_puppet wires serial_X."""
import os
import sys
import xml.etree.ElementTree as ET

import pytest
import roslaunch.config

LAUNCH = os.path.join(os.path.dirname(__file__), '..', '..', 'launch', 'arm.launch')
TABLE_5 = {'arm_side': 'L', 'port_name': '/dev/ttyACM0', 'comm_rate': '10.0',
           'frame_rate': '8.0', 'debug_mode': 'true'}


def load(*args):
    """Return {node name: node} and the params of arm.launch run with the given arguments."""
    saved = sys.argv
    sys.argv = ['roslaunch', 'robopuppet', 'arm.launch'] + list(args)
    try:
        config = roslaunch.config.load_config_default([LAUNCH], None)
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
