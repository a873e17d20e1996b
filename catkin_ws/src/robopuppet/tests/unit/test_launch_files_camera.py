"""launch/camera.launch: documented arguments, defaulting to the camera node's, wired through."""
import os
import sys
import xml.etree.ElementTree as ET

import roslaunch.config

from robopuppet.cameras import webcam

LAUNCH = os.path.join(os.path.dirname(__file__), '..', '..', 'launch', 'camera.launch')
ARGS = ('name', 'device', 'width', 'height', 'rate', 'quality', 'hfov_deg')


def load(*args):
    """Return {node name: node} and {param: value} of camera.launch run with the arguments."""
    saved = sys.argv
    sys.argv = ['roslaunch', 'robopuppet', 'camera.launch'] + list(args)
    try:
        config = roslaunch.config.load_config_default([LAUNCH], None)
    finally:
        sys.argv = saved
    return {n.name: n for n in config.nodes}, {k: p.value for k, p in config.params.items()}


def test_every_argument_is_documented_and_defaults_to_the_nodes_default():
    args = {a.get('name'): a for a in ET.parse(LAUNCH).getroot().iter('arg')}
    assert set(args) == set(ARGS)
    assert all(a.get('doc') for a in args.values())
    for name in ARGS:
        assert str(webcam.DEFAULTS[name]) == args[name].get('default'), name


def test_the_defaults_read_back_as_the_nodes_default_settings():
    nodes, params = load()
    assert list(nodes) == ['camera_room_camera']
    assert nodes['camera_room_camera'].type == 'camera'
    given = {k.rpartition('/')[2]: v for k, v in params.items() if k.startswith('/camera_')}
    read = webcam.read_settings(lambda name, default: given.get(name, default))
    assert read == webcam.read_settings(lambda name, default: default)


def test_arguments_reach_the_node_named_after_the_camera():
    nodes, params = load('name:=bench_webcam', 'device:=1', 'width:=320', 'height:=240',
                         'rate:=30', 'quality:=95')
    assert list(nodes) == ['camera_bench_webcam']
    given = {k.rpartition('/')[2]: v for k, v in params.items()
             if k.startswith('/camera_bench_webcam/')}
    s = webcam.read_settings(lambda name, default: given.get(name, default))
    assert (s.name, s.device, s.width, s.height, s.rate_hz, s.quality) == (
        'bench_webcam', 1, 320, 240, 30.0, 95)
