"""Unit tests of the launch files: arguments, each default in one place, how the nodes are wired."""
import glob
import os
import sys
import xml.etree.ElementTree as ET

import pytest
import roslaunch.arg_dump
import roslaunch.config
import rospkg

from robopuppet import interface

LAUNCH_DIR = os.path.join(os.path.dirname(__file__), '..', '..', 'launch')
TEST_DIR = os.path.join(os.path.dirname(__file__), '..', 'integration')
LAUNCH = os.path.join(LAUNCH_DIR, 'arm.launch')
LAUNCH_FILES = ('arm.launch', 'puppet.launch', 'main_sim.launch', 'baxter_sim.launch',
                'ghost.launch', 'recorder.launch', 'operator.launch', 'robot.launch',
                'diagnostics.launch')
# The 2020 system's launch defaults, but frame_rate: 30 Hz (pyqtgraph) where the 2020 Tk GUI used 8.
LAUNCH_2020 = {'arm_side': 'L', 'port_name': '/dev/ttyACM0', 'comm_rate': '10.0',
           'frame_rate': '30.0', 'debug_mode': 'true'}
# An argument that a file declares with another default than the file it includes, on purpose.
OVERRIDES = {('main_sim.launch', 'run_side_L'): 'the simulated system runs the right arm only',
             ('puppet.launch', 'gui'): 'arm.launch alone opens no GUI; puppet.launch one per arm',
             ('operator.launch', 'record_sides'): 'the operator host records the arms it runs'}
# An argument of an included file that the including file does not offer its user.
NOT_OFFERED = {
    ('puppet.launch', 'sim_link'): 'one link per arm: sim_link_prefix names both',
    ('puppet.launch', 'events'): "one event source per arm: input.launch's, per side",
    ('robot.launch', 'device'): "the operator host's",
    ('operator.launch', 'max_sample_age'): "arm_X's, on the robot host",
    ('operator.launch', 'zones_file'): "arm_X's, on the robot host",
    **{('robot.launch', arg): "the operator host's" for arg in (
        'port_L', 'port_R', 'frame_rate', 'debug_mode', 'sim_puppet', 'sim_link_prefix')},
    ('main_sim.launch', 'sim_robot'): 'the simulated system always runs the stand-in',
    ('main_sim.launch', 'port_L'): 'the simulated puppets have no serial port',
    ('main_sim.launch', 'port_R'): 'the simulated puppets have no serial port'}


def load_config(*args, launch=LAUNCH):
    """Return the roslaunch config of a launch file run with the given arguments."""
    saved = sys.argv
    sys.argv = ['roslaunch', 'robopuppet', os.path.basename(launch)] + list(args)
    try:
        return roslaunch.config.load_config_default([launch], None)
    finally:
        sys.argv = saved


def load(*args, launch=LAUNCH):
    """Return {node name: node} and the params of a launch file run with the given arguments."""
    config = load_config(*args, launch=launch)
    return {n.name: n for n in config.nodes}, {k: p.value for k, p in config.params.items()}


def user_args(root):
    """Return {name: (default or None, doc)} of a launch file's own arguments (not value=)."""
    return {a.get('name'): (a.get('default'), a.get('doc')) for a in root.findall('arg')
            if a.get('value') is None}


def include_edges(launch_dir):
    """Return {file: {arg: (default, doc)}} and {file: [(included file, {args it sets})]}."""
    args, edges = {}, {}
    for path in glob.glob(os.path.join(launch_dir, '*.launch')):
        root, name = ET.parse(path).getroot(), os.path.basename(path)
        args[name] = user_args(root)
        edges[name] = [(os.path.basename(i.get('file')), {a.get('name') for a in i.findall('arg')})
                       for i in root.iter('include')]
    return args, edges


def args_not_offered(launch_dir, not_offered=()):
    """Return (file, arg, included file): an argument of an included file, not set by the
    include, that the including file neither declares (so that roslaunch's ros-args option
    lists it) nor lists in not_offered."""
    args, edges = include_edges(launch_dir)
    return sorted({(name, arg, child) for name in args for child, given in edges[name]
                   for arg in args.get(child, {}).keys() - given - args[name].keys()
                   if (name, arg) not in not_offered})


def defaults_that_disagree(launch_dir, overrides=()):
    """Return (file, arg, default, included file, its default) for each argument whose default
    differs from the one of a file it passes on to, but the given overrides."""
    args, edges = include_edges(launch_dir)
    return sorted({(name, arg, args[name][arg][0], child, args[child][arg][0])
                   for name in args for child, given in edges[name]
                   for arg in args[name].keys() & args.get(child, {}).keys() - given
                   if args[name][arg][0] != args[child][arg][0] and (name, arg) not in overrides})


def test_arguments_of_table_5_plus_sim_puppet_and_gui_all_documented():
    args = {a.get('name'): a for a in ET.parse(LAUNCH).getroot().iter('arg')}
    for name, default in dict(LAUNCH_2020, sim_puppet='false', gui='false').items():
        assert args[name].get('default') == default, name
    assert all(a.get('doc') for a in args.values())


def test_every_argument_of_an_included_file_is_offered_by_the_including_file():
    assert args_not_offered(LAUNCH_DIR, NOT_OFFERED) == []


def test_each_default_agrees_with_the_file_it_passes_on_to():
    assert defaults_that_disagree(LAUNCH_DIR, OVERRIDES) == []


def test_each_deliberate_override_differs_from_the_default_it_overrides():
    args, edges = include_edges(LAUNCH_DIR)
    for name, arg in OVERRIDES:
        below = {args[c][arg][0] for c, given in edges[name] if arg in args[c].keys() - given}
        assert below and args[name][arg][0] not in below, (name, arg)


def test_the_checks_find_an_argument_hidden_or_defaulted_otherwise(tmp_path):
    (tmp_path / 'top.launch').write_text(
        '<launch><arg name="rate" default="5.0"/><include file="arm.launch"/></launch>')
    (tmp_path / 'arm.launch').write_text(
        '<launch><arg name="rate" default="10.0"/><arg name="port" default="/dev/x"/></launch>')
    assert defaults_that_disagree(str(tmp_path)) == [
        ('top.launch', 'rate', '5.0', 'arm.launch', '10.0')]
    assert args_not_offered(str(tmp_path)) == [('top.launch', 'port', 'arm.launch')]


@pytest.mark.parametrize('name', ['main_sim.launch', 'operator.launch', 'robot.launch',
                                  'puppet.launch', 'arm.launch'])
def test_ros_args_lists_every_argument_with_a_doc(name):
    """What `roslaunch --ros-args robopuppet NAME` prints (roslaunch.arg_dump)."""
    listed = roslaunch.arg_dump.get_args([os.path.join(LAUNCH_DIR, name)])
    declared = user_args(ET.parse(os.path.join(LAUNCH_DIR, name)).getroot())
    assert set(listed) == set(declared) and all(doc for doc, _ in listed.values())
    if name == 'main_sim.launch':  # what an operator sets most, which it once hid
        assert {'comm_rate', 'gui', 'rviz', 'zones_file', 'sim_link_prefix',
                'episodes_dir', 'diagnostics'} <= set(listed)


def test_puppet_launch_runs_without_arguments():
    nodes, params = load(launch=os.path.join(LAUNCH_DIR, 'puppet.launch'))
    assert {'config_L', 'serial_L', 'gui_L', 'arm_L', 'config_R', 'serial_R', 'arm_R'} <= set(nodes)
    assert params['/serial_L/port_name'] != params['/serial_R/port_name']


@pytest.mark.parametrize('launch', ['puppet.launch', 'operator.launch'])
def test_a_puppet_alone_defaults_to_arm_launchs_port(launch):
    arm_default = LAUNCH_2020['port_name']
    for side, other in (('L', 'R'), ('R', 'L')):
        _, params = load('run_side_%s:=false' % other, 'gui:=false', 'rviz:=false',
                         launch=os.path.join(LAUNCH_DIR, launch))
        assert params['/serial_%s/port_name' % side] == arm_default, side


def test_the_comm_rate_default_is_the_firmwares_rate_of_the_interface_table():
    _, params = load('sim_puppet:=true')
    for name in ('/serial_L/comm_rate', '/puppet_sim_L/state_rate', '/arm_L/comm_rate'):
        assert float(params[name]) == interface.DEFAULT_COMM_RATE_HZ, name


@pytest.mark.parametrize('launch, args, sides', [
    ('main_sim.launch', ['comm_rate:=5', 'rviz:=false', 'gui:=false'], 'R'),
    ('main_sim.launch', ['comm_rate:=5', 'run_side_L:=true', 'rviz:=false', 'gui:=false'], 'LR'),
    ('operator.launch', ['comm_rate:=5', 'sim_puppet:=true', 'gui:=false'], ''),
    ('robot.launch', ['comm_rate:=5'], 'LR'),
    ('arm.launch', ['comm_rate:=5', 'arm_side:=R', 'sim_puppet:=true'], 'R'),
])
def test_comm_rate_reaches_the_serial_node_the_simulator_and_the_arm_controller(launch, args,
                                                                                sides):
    nodes, params = load(*args, launch=os.path.join(LAUNCH_DIR, launch))
    for side in sides:
        assert params['/arm_%s/comm_rate' % side] == 5
    for side in sides if launch != 'robot.launch' else '':
        for name in ('/serial_%s/comm_rate', '/puppet_sim_%s/state_rate'):
            assert params[name % side] == 5, name % side
    assert {n for n in nodes if n.startswith('arm_')} == {'arm_' + s for s in sides}
    if launch == 'operator.launch':
        for side in 'LR':
            assert params['/serial_%s/comm_rate' % side] == 5


@pytest.mark.parametrize('side', ['L', 'R'])
def test_sim_puppet_points_serial_at_the_simulator(side):
    nodes, params = load('arm_side:=' + side, 'sim_puppet:=true', 'comm_rate:=50.0')
    assert {'config_' + side, 'serial_' + side, 'puppet_sim_' + side} <= set(nodes)
    link = '%s_arm_%s' % (interface.sim_link_prefix(os.environ['ROS_MASTER_URI'],
                                                     rospkg.get_ros_home()), side)
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


@pytest.mark.parametrize('launch, args', [
    ('arm.launch', ['arm_side:=R']), ('arm.launch', ['arm_side:=L', 'host:=operator']),
    ('main_sim.launch', []), ('operator.launch', ['run_side_L:=false'])])
def test_the_config_node_respawns_soon_after_it_dies(launch, args):
    """A config node killed mid-calibration comes back, so that Undo can run."""
    nodes, _ = load(*args, launch=os.path.join(LAUNCH_DIR, launch))
    configs = [node for name, node in nodes.items() if name.startswith('config_')]
    assert configs
    for node in configs:
        assert node.respawn and 0 < node.respawn_delay <= 2.0, node.name


@pytest.mark.parametrize('name', LAUNCH_FILES)
def test_every_argument_is_documented(name):
    args = ET.parse(os.path.join(LAUNCH_DIR, name)).getroot().findall('arg')
    undocumented = [a.get('name') for a in args if not a.get('doc')]
    assert undocumented == []


def test_main_sim_runs_the_right_arm_on_simulated_hardware_by_default():
    nodes, params = load('rviz:=false', 'gui:=false',
                         launch=os.path.join(LAUNCH_DIR, 'main_sim.launch'))
    assert {'baxter_sim', 'robot_state_publisher', 'sim_cameras', 'config_R', 'serial_R',
            'puppet_sim_R', 'arm_R', 'ghost', 'recorder', 'diagnostic_aggregator'} == set(nodes)
    assert params['/serial_R/port_name'] == params['/puppet_sim_R/port_link']


@pytest.mark.parametrize('launch, args, sides, sim', [
    ('main_sim.launch', [], 'R', True),
    ('main_sim.launch', ['run_side_L:=true'], 'LR', True),
    ('main_sim.launch', ['run_side_L:=true', 'record_sides:=L'], 'L', True),
    ('recorder.launch', [], 'LR', False),
])
def test_the_recorder_records_the_arms_that_run(launch, args, sides, sim):
    nodes, params = load('rviz:=false', 'gui:=false', 'episodes_dir:=/tmp/ep', *args,
                         launch=os.path.join(LAUNCH_DIR, launch))
    assert nodes['recorder'].type == 'recorder'
    assert params['/recorder/sides'] == sides and params['/recorder/sim'] is sim
    assert params['/recorder/episodes_dir'] == '/tmp/ep'


@pytest.mark.parametrize('launch', ['main_sim.launch', 'operator.launch'])
def test_the_ghost_has_a_prefixed_description_and_its_own_state_publisher(launch):
    config = load_config('rviz:=false', 'gui:=false', launch=os.path.join(LAUNCH_DIR, launch))
    nodes = {(n.namespace, n.name): n for n in config.nodes}
    assert ('/ghost/', 'robot_state_publisher') in nodes and ('/ghost/', 'ghost') in nodes
    ghost = ET.fromstring(config.params['/ghost/robot_description'].value)
    assert ghost.find('link').get('name').startswith('ghost/')
    assert config.params['/ghost/ghost/prefix'].value == 'ghost/'
    assert '/ghost/ghost/target_topic' not in config.params  # the puppet's ghost
    # The calibration target ghost: its own description, state publisher and topic.
    assert ('/target/', 'robot_state_publisher') in nodes and ('/target/', 'ghost') in nodes
    target = ET.fromstring(config.params['/target/robot_description'].value)
    assert target.find('link').get('name').startswith('target/')
    assert config.params['/target/ghost/prefix'].value == 'target/'
    assert config.params['/target/ghost/target_topic'].value == interface.CALIBRATION_TARGET
    if launch == 'operator.launch':  # the robot host (or Baxter) publishes the description
        assert '/robot_description' not in config.params
        rviz, = (n for n in load_config(launch=os.path.join(LAUNCH_DIR, launch)).nodes
                 if n.name == 'rviz')
        assert 'real_robot.rviz' in rviz.args


def test_main_sim_passes_its_arguments_on_as_run_sh_gives_them():
    nodes, params = load('rviz:=false', 'gui:=false', 'sim_link_prefix:=/run/user/7/rp',
                         'run_side_L:=true', 'frame_rate:=12',
                         launch=os.path.join(LAUNCH_DIR, 'main_sim.launch'))
    assert 'rviz' not in nodes and not any(n.startswith('gui_') for n in nodes)
    for side in 'LR':
        assert params['/puppet_sim_%s/port_link' % side] == '/run/user/7/rp_arm_' + side
    nodes, params = load('frame_rate:=12', launch=os.path.join(LAUNCH_DIR, 'main_sim.launch'))
    assert {'rviz', 'gui_R'} <= set(nodes) and params['/gui_R/frame_rate'] == 12
    assert params['/gui_R/sim_puppet'] is True


def test_the_operator_host_gives_each_side_its_own_port():
    nodes, params = load('gui:=false', 'rviz:=false',
                         launch=os.path.join(LAUNCH_DIR, 'operator.launch'))
    assert {'serial_L', 'serial_R', 'config_L', 'config_R'} <= set(nodes)
    assert 'puppet_sim_L' not in nodes and 'gui_L' not in nodes
    assert params['/serial_L/port_name'] != params['/serial_R/port_name']
    assert params['/recorder/sides'] == 'LR'
    nodes, params = load('run_side_L:=false', 'port_R:=/dev/ttyACM0',
                         launch=os.path.join(LAUNCH_DIR, 'operator.launch'))
    assert {'serial_R', 'gui_R', 'rviz'} <= set(nodes) and 'serial_L' not in nodes
    assert params['/serial_R/port_name'] == '/dev/ttyACM0'
    assert params['/recorder/sides'] == 'R'


@pytest.mark.parametrize('launch, args, runs', [
    ('operator.launch', ['sim_puppet:=true'],
     {'config_L', 'serial_L', 'puppet_sim_L', 'gui_L', 'recorder', 'rviz', 'ghost'}),
    ('robot.launch', [], {'arm_L', 'arm_R', 'baxter_sim', 'robot_state_publisher',
                          'sim_cameras', 'diagnostic_aggregator'}),
    ('robot.launch', ['sim_cameras:=false'],
     {'arm_L', 'arm_R', 'baxter_sim', 'robot_state_publisher', 'diagnostic_aggregator'}),
    ('robot.launch', ['sim_robot:=false', 'run_side_L:=false', 'diagnostics:=false'],
     {'arm_R'}),
])
def test_each_host_runs_its_own_nodes_only(launch, args, runs):
    config = load_config(*args, launch=os.path.join(LAUNCH_DIR, launch))
    nodes = {n.name for n in config.nodes}
    assert runs <= nodes
    if launch == 'operator.launch':  # arm_X decides on the robot host, beside Baxter
        assert not any(n.startswith('arm_') or n == 'baxter_sim' for n in nodes)
    else:
        assert nodes == runs  # nothing of the operator's: no serial, config, GUI or RViz
    assert ('/robot_description' in config.params) == ('baxter_sim' in nodes)


def test_an_unknown_host_is_refused_by_name():
    with pytest.raises(Exception, match='host:=kitchen is not operator, robot or both'):
        load('host:=kitchen')


@pytest.mark.parametrize('path', sorted(
    p for p in glob.glob(os.path.join(TEST_DIR, '*.test'))
    if any(n in open(p).read() for n in LAUNCH_FILES)))
def test_every_rostest_file_that_includes_a_launch_file_still_loads(path):
    nodes, _ = load(launch=path)
    assert any(n.startswith(('serial_', 'baxter_sim', 'recorder')) for n in nodes), nodes


def test_the_simulated_puppets_link_is_unique_per_master_and_in_ros_home(monkeypatch, tmp_path):
    links = set()
    for uri in ('http://localhost:11311', 'http://localhost:11312', 'http://robot:11311/'):
        monkeypatch.setenv('ROS_MASTER_URI', uri)
        monkeypatch.setenv('ROS_HOME', str(tmp_path))
        _, params = load('rviz:=false', 'gui:=false',
                         launch=os.path.join(LAUNCH_DIR, 'main_sim.launch'))
        link = params['/puppet_sim_R/port_link']
        assert link == params['/serial_R/port_name'] == '%s_arm_R' % interface.sim_link_prefix(
            uri, str(tmp_path))
        assert link.startswith(str(tmp_path) + '/robopuppet/')
        links.add(link)
    assert len(links) == 3


def test_the_aggregator_groups_every_status_the_nodes_publish():
    """config/diagnostics.yaml: each RoboPuppet status name matches exactly one analyzer."""
    import yaml
    from robopuppet.cameras import camera_node
    config = yaml.safe_load(open(os.path.join(LAUNCH_DIR, '..', 'config', 'diagnostics.yaml')))
    analyzers = config['analyzers']['robopuppet']['analyzers'].values()
    names = ['/serial_R: ' + interface.DIAG_LINK, 'arm_L: ' + interface.DIAG_TELEOP,
             'arm_R: ' + interface.DIAG_NETWORK, '/camera_room: %s room' % camera_node.DIAG_CAMERA,
             '/sim_cameras: simulated cameras']
    for name in names:
        assert sum(any(c in name for c in a['contains']) for a in analyzers) == 1, name
    nodes, params = load(launch=os.path.join(LAUNCH_DIR, 'robot.launch'))
    assert nodes['diagnostic_aggregator'].package == 'diagnostic_aggregator'
    assert params['/diagnostic_aggregator/analyzers/robopuppet/path'] == 'RoboPuppet'


def test_the_stand_ins_state_publisher_keeps_quiet_about_baxters_fixed_torso_joint():
    nodes, _ = load(launch=os.path.join(LAUNCH_DIR, 'baxter_sim.launch'))
    env = dict(nodes['robot_state_publisher'].env_args)
    text = open(env['ROSCONSOLE_CONFIG_FILE']).read()
    assert 'log4j.logger.ros.robot_state_publisher=ERROR' in text
