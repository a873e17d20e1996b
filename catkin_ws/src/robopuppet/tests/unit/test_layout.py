"""The library's imports run downward only, and its modules keep their sizes.

The map (folder, what it may import, which modules talk to ROS) is written once, in
robopuppet/__init__.py's docstring; this test reads it there. A pure core must not import rospy,
ROS message packages or Qt; no module may import a node adapter (only the executables in nodes/
do); a ROS adapter is at most 150 lines and any other module at most 300, but for SIZE_EXCEPTIONS.
"""
import ast
import pathlib
import re

import pytest

SRC_DIR = pathlib.Path(__file__).resolve().parents[2] / 'src' / 'robopuppet'
ADAPTER_LINES = 150
MODULE_LINES = 300
# module -> why it stays over its size (a split would scatter one thing over two files).
SIZE_EXCEPTIONS = {
    'episodes.recorder_node': 'its callbacks take its two locks (an episode\'s start or stop with '
                              'its subscriptions, then the Recorder) in one order, readable in one '
                              'place; its pure work is in session, recording, recorder_params and '
                              'recorder_claim',
}


def layer_map(docstring):
    """Return ({subsystem: the subsystems it may import}, {ROS adapter}) from the map's text.

    The subsystems are the table's folders ('tables' for the top level); the ROS adapters are
    the dotted names listed under 'ROS adapters besides the nodes:'.
    """
    layers, folder = {}, None
    for line in docstring.splitlines():
        cells = [c.strip() for c in line.split('|')[1:-1]]
        if len(cells) != 3 or set(cells[0]) <= set('-') and cells[0]:
            continue
        if cells[0] == 'folder':
            continue
        if cells[0]:
            folder = 'tables' if cells[0] == '(top level)' else cells[0].rstrip('/')
            layers[folder] = set()
        layers[folder] |= {name for name in re.split(r'[,\s]+', cells[1]) if name}
    for folder, allowed in layers.items():
        allowed.discard('tables')
        allowed.discard(folder)
    listed = docstring.split('ROS adapters besides the nodes:', 1)[1].split('\n\n', 1)[0]
    adapters = set(re.findall(r'^- `([\w.]+)`', listed, re.MULTILINE))
    return layers, adapters


LAYERS, ADAPTERS = layer_map(ast.get_docstring(ast.parse((SRC_DIR / '__init__.py').read_text())))
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


def is_adapter(module):
    """Return whether the map lets a module talk to ROS (a node or a listed adapter)."""
    return module.endswith('_node') or module in ADAPTERS


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
    if not is_adapter(module):
        if roots & ROS_MODULES:
            found.append('%s is a pure core but imports %s' % (module, sorted(roots & ROS_MODULES)))
        if roots & QT_MODULES and own != QT_MODULES_OK:
            found.append('%s imports Qt' % module)
    return found


MODULES = library_modules()


def test_the_layer_map_names_the_folders():
    folders = {p.name for p in SRC_DIR.iterdir() if p.is_dir() and p.name != '__pycache__'}
    assert folders == set(LAYERS) - {'tables'}
    assert ADAPTERS <= set(MODULES)
    assert all(allowed <= set(LAYERS) for allowed in LAYERS.values())


def test_the_map_lists_only_modules_that_talk_to_ros():
    # A listed module that no longer imports ROS would switch the pure-core check off for nothing.
    assert [m for m in sorted(ADAPTERS) if not set(
        name.split('.')[0] for name in imports_of(MODULES[m])) & ROS_MODULES] == []


def test_the_map_reads_its_table_and_list():
    layers, adapters = layer_map("""
| folder      | may import        | what |
|-------------|-------------------|------|
| (top level) | tables            | a    |
| a/          | tables, b         | b    |
|             | c                 | c    |

ROS adapters besides the nodes:
- `a.x`: why
- `b.y`: why

Not this: `c.z`.
""")
    assert layers == {'tables': set(), 'a': {'b', 'c'}}
    assert adapters == {'a.x', 'b.y'}


def line_limit(module):
    """Return the most lines a module may have: 150 for a ROS adapter, else 300."""
    return ADAPTER_LINES if is_adapter(module) else MODULE_LINES


@pytest.mark.parametrize('module', sorted(m for m in MODULES if m))
def test_modules_keep_their_size(module):
    lines = len(MODULES[module].read_text().splitlines())
    if module in SIZE_EXCEPTIONS:
        assert lines > line_limit(module), '%s is back within its size: drop its exception' % module
    else:
        assert lines <= line_limit(module), (
            '%s has %d lines, over %d: split it by responsibility (house style "Size")'
            % (module, lines, line_limit(module)))


def test_every_size_exception_is_a_module_with_a_reason():
    assert set(SIZE_EXCEPTIONS) <= set(MODULES)
    assert all(len(reason) > 20 for reason in SIZE_EXCEPTIONS.values())


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


# Unit tests of what is not a library module: the tree, the docs, the launch files, the
# messages, the tests' own fixtures, and the GUI's window as a whole.
WHOLE_TREE_TESTS = {'layout', 'architecture_doc', 'launch_files', 'baxter_msgs', 'hand_pose',
                    'gui_operator', 'gui_widgets'}


def module_tested_by(test_name):
    """Return the library module a unit test file is named after (test_<module>[_<aspect>]),
    or None."""
    parts = test_name[len('test_'):].split('_')
    names = {m.rpartition('.')[2] for m in MODULES if m}
    prefixes = ['_'.join(parts[:n]) for n in range(len(parts), 0, -1)]
    return next((p for p in prefixes if p in names), None)


def test_each_unit_test_file_is_named_after_its_module():
    tests = sorted(p.stem for p in pathlib.Path(__file__).parent.glob('test_*.py'))
    unnamed = [t for t in tests if module_tested_by(t) is None
               and not any(t == 'test_' + w or t.startswith('test_%s_' % w)
                           for w in WHOLE_TREE_TESTS)]
    assert unnamed == [], 'name each after the module it tests: test_<module>[_<aspect>].py'
