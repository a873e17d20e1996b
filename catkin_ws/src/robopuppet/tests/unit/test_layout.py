"""The library's imports run downward only: node adapters -> pure cores -> shared tables.

The map (folder, role, what it may import) is robopuppet/__init__.py's docstring; LAYERS below
is the same map as data. A pure core must not import rospy, ROS message packages or Qt, and no
module may import a node adapter (only the executables in nodes/ do).
"""
import ast
import pathlib

import pytest

SRC_DIR = pathlib.Path(__file__).resolve().parents[2] / 'src' / 'robopuppet'

# subsystem -> the subsystems it may import (besides itself and the shared tables).
LAYERS = {
    'tables': set(),
    'config': set(),
    'baxter_sim': {'world'},
    'protocol': set(),
    'arm': {'world'},
    'puppet_sim': {'protocol'},
    'calibration': set(),
    'gui': {'arm', 'calibration', 'config', 'episodes', 'puppet_sim'},
    'ghost': {'arm'},
    'episodes': {'arm', 'config'},
    'cameras': {'world'},
    'world': set(),
}
# The modules that may talk to ROS: the node adapters (named *_node; only the executables in
# nodes/ import them) and the adapters they use.
ADAPTERS = {
    'config.config_node', 'protocol.serial_node', 'arm.arm_node', 'arm.link_topics',
    'arm.zone_topics',
    'puppet_sim.puppet_sim_node', 'baxter_sim.baxter_sim_node', 'gui.gui_node',
    'gui.puppet_client', 'ghost.ghost_node', 'calibration.calibrate_node',
    'episodes.export_files', 'episodes.recorder_node', 'episodes.episode_files',
    'episodes.replay_node', 'episodes.puppet_player', 'episodes.player',
    'cameras.camera_node', 'cameras.republish_node', 'gui.camera_client',
    'cameras.sim_camera_node', 'cameras.node_loops',
    'link_recovery',   # the nodes' shared watch on rospy's connections across the link
    'shape_markers',   # RViz markers of shapes: the zones (arm_X) and the room (sim_cameras)
}
# The GUI's widgets are Qt by nature; they may import Qt but not rospy.
QT_MODULES_OK = 'gui'
ROS_MODULES = {'rospy', 'rospkg', 'rosgraph', 'rosbag', 'genpy', 'roslib', 'tf2_ros',
               'std_msgs', 'sensor_msgs', 'geometry_msgs', 'diagnostic_msgs', 'tf2_msgs',
               'baxter_core_msgs', 'robopuppet_msgs', 'visualization_msgs'}
QT_MODULES = {'PyQt5', 'pyqtgraph'}


def library_modules():
    """Return {dotted name below robopuppet: path} of every module in the source tree."""
    modules = {}
    for path in sorted(SRC_DIR.rglob('*.py')):
        parts = path.relative_to(SRC_DIR).with_suffix('').parts
        if parts[-1] == '__init__':
            parts = parts[:-1]
        modules['.'.join(parts)] = path
    return modules


def subsystem(module):
    """Return the subsystem of a dotted module name below robopuppet ('tables' at top level)."""
    head = module.split('.')[0]
    return head if head in LAYERS else 'tables'


def imports_of(path):
    """Return the dotted names a module imports (absolute imports only: the house style)."""
    names = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            names.extend(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            assert node.level == 0, '%s: relative import' % path
            names.append(node.module)
            names.extend('%s.%s' % (node.module, alias.name) for alias in node.names)
    return names


def robopuppet_targets(names, modules):
    """Return the library modules among imported names (robopuppet.x.y -> 'x.y')."""
    targets = set()
    for name in names:
        if name.startswith('robopuppet.'):
            inner = name[len('robopuppet.'):]
            while inner and inner not in modules:
                inner = inner.rpartition('.')[0]
            if inner:
                targets.add(inner)
    return targets


def problems(module, names, modules):
    """Return what is wrong with `module` (dotted, below robopuppet) importing `names`."""
    found = []
    own = subsystem(module)
    for target in sorted(robopuppet_targets(names, modules)):
        other = subsystem(target)
        if other not in {own, 'tables'} | LAYERS[own]:
            found.append('%s (%s) imports %s (%s): against the layer map'
                         % (module, own, target, other))
        if target.endswith('_node'):
            found.append('%s imports the node adapter %s' % (module, target))
    roots = {name.split('.')[0] for name in names}
    if module not in ADAPTERS:
        if roots & ROS_MODULES:
            found.append('%s is a pure core but imports %s' % (module, sorted(roots & ROS_MODULES)))
        if roots & QT_MODULES and own != QT_MODULES_OK:
            found.append('%s imports Qt' % module)
    return found


MODULES = library_modules()


def test_the_layer_map_names_the_folders():
    folders = {p.name for p in SRC_DIR.iterdir() if p.is_dir() and p.name != '__pycache__'}
    assert folders == set(LAYERS) - {'tables'}
    assert set(ADAPTERS) <= set(MODULES)
    assert {m for m in MODULES if m.endswith('_node')} <= ADAPTERS


@pytest.mark.parametrize('module', sorted(m for m in MODULES if m))
def test_imports_run_downward(module):
    assert problems(module, imports_of(MODULES[module]), MODULES) == []


@pytest.mark.parametrize('module, source, expected', [
    ('settings', 'from robopuppet.arm import teleop', 'against the layer map'),
    ('protocol.codec', 'import rospy', 'pure core'),
    ('arm.teleop', 'from robopuppet.gui import state', 'against the layer map'),
    ('arm.teleop', 'from robopuppet.arm.arm_node import main', 'node adapter'),
    ('protocol.codec', 'from robopuppet.config import config_store', 'against the layer map'),
    ('arm.joint_motion', 'from PyQt5 import QtCore', 'imports Qt'),
])
def test_the_checker_catches_violations(tmp_path, module, source, expected):
    path = tmp_path / 'module.py'
    path.write_text(source + '\n')
    found = problems(module, imports_of(path), MODULES)
    assert found and expected in found[0]
