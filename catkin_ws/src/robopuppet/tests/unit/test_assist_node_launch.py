"""launch/assist.launch and its argument assist_model on robot.launch and main_sim.launch: the
assist node only when a model is named, its orange ghost in /assist, RViz's display of it."""
import os
import sys
import xml.etree.ElementTree as ET

import pytest
import roslaunch.config
import yaml

from robopuppet import interface
from robopuppet.ghost import ghost_urdf

PACKAGE = os.path.join(os.path.dirname(__file__), '..', '..')
LAUNCH_DIR = os.path.join(PACKAGE, 'launch')


def load(launch, *args):
    """Return {(namespace, name): node} and {param: value} of a launch file with arguments."""
    saved = sys.argv
    sys.argv = ['roslaunch', 'robopuppet', launch] + list(args)
    try:
        config = roslaunch.config.load_config_default([os.path.join(LAUNCH_DIR, launch)], None)
    finally:
        sys.argv = saved
    return ({(n.namespace, n.name): n for n in config.nodes},
            {k: p.value for k, p in config.params.items()})


@pytest.mark.parametrize('launch', ['robot.launch', 'main_sim.launch'])
def test_no_assist_without_a_model(launch):
    nodes, params = load(launch, 'rviz:=false', 'gui:=false')
    assert not any(name == 'assist' or ns == '/assist/' for ns, name in nodes)
    assert '/assist/robot_description' not in params


@pytest.mark.parametrize('launch', ['robot.launch', 'main_sim.launch'])
def test_a_model_runs_the_assist_node_and_its_ghost(launch):
    nodes, params = load(launch, 'rviz:=false', 'gui:=false', 'assist_model:=/tmp/tray.npz')
    assert nodes[('/', 'assist')].type == 'assist'
    assert params['/assist/model'] == '/tmp/tray.npz'
    assert ('/assist/', 'robot_state_publisher') in nodes
    assert nodes[('/assist/', 'ghost')].type == 'ghost'
    assert params['/assist/ghost/prefix'] == 'assist/'
    assert params['/assist/ghost/target_topic'] == interface.ASSIST_PREDICTION
    description = ET.fromstring(params['/assist/robot_description'])
    assert description.find('link').get('name').startswith('assist/')
    colour = description.find('.//color').get('rgba').split()
    red, green, blue = (float(c) for c in colour[:3])
    assert red > green > blue  # orange, told from the blue ghost and the green target


def test_the_assist_tint_is_orange():
    red, green, blue = ghost_urdf.TINTS['assist']
    assert red > 0.9 and 0.3 < green < 0.7 and blue < 0.3


def test_rviz_shows_the_assist_ghost():
    with open(os.path.join(PACKAGE, 'rviz', 'robopuppet.rviz')) as config:
        displays = yaml.safe_load(config)['Visualization Manager']['Displays']
    assist, = (d for d in displays if d.get('Robot Description') == '/assist/robot_description')
    assert assist['Class'] == 'rviz/RobotModel' and assist['Enabled']
    assert assist['Name'] == 'Assist: the predicted arm'
