"""Tests of robopuppet.world.obstacles (the obstacle file: which one, its refusals) and of how
baxter_sim takes it: a file that cannot be used is one error line, and the node runs without
obstacles; the shipped config/bed_obstacles.yaml is the world's bed, and keeps the neutral
pose clear."""
import os

import pytest
import rospkg
import rospy

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim import baxter_params
from robopuppet.world import obstacles

PACKAGE = os.path.join(os.path.dirname(__file__), '..', '..')
BED = os.path.join(PACKAGE, 'config', 'bed_obstacles.yaml')
URDF = open(bd.URDF_PATH).read()
DESC = bd.Description(URDF)


def package_with_default_file(tmp_path):
    (tmp_path / 'config').mkdir()
    (tmp_path / 'config' / 'obstacles.yaml').write_text(open(BED).read())
    return str(tmp_path)


def test_the_parameter_chooses_the_file(tmp_path):
    assert obstacles.chosen_path(None, str(tmp_path)) is None     # no default file: none
    package = package_with_default_file(tmp_path)
    assert obstacles.chosen_path(None, package) == obstacles.default_path(package) == \
        os.path.join(package, 'config', 'obstacles.yaml')
    assert obstacles.chosen_path('', package) is None
    assert obstacles.chosen_path('/x/table.yaml', package) == '/x/table.yaml'


@pytest.mark.parametrize('text, words', [
    ('shapes: [', 'not YAML'),
    ('frame: world\nshapes: []', "'base' frame"),
    ('shapes:\n  - {name: t, type: box, size: [1, 1], xyz: [0, 0, 0]}', "'t': size"),
    ('shapes:\n  - {name: t, type: cone, xyz: [0, 0, 0]}', 'type must be'),
])
def test_a_malformed_file_is_refused_naming_file_and_entry(tmp_path, text, words):
    path = tmp_path / 'obstacles.yaml'
    path.write_text(text)
    with pytest.raises(obstacles.ObstacleFileError, match=words) as error:
        obstacles.load_obstacles(str(path))
    assert str(path) in str(error.value)
    with pytest.raises(obstacles.ObstacleFileError, match='cannot read obstacle file'):
        obstacles.load_obstacles(str(tmp_path / 'missing.yaml'))


def test_the_shipped_obstacles_are_the_worlds_bed_not_the_patient():
    from robopuppet.cameras import scene
    world = {s.name: s for s in scene.load_world(os.path.join(PACKAGE, 'config',
                                                              'world.yaml')).shapes}
    shipped = obstacles.load_obstacles(BED)
    assert {s.name for s in shipped} == {'bed_frame', 'mattress', 'bed_headboard',
                                         'bed_footboard'}
    assert all(s == world[s.name] for s in shipped)   # drawn where they block


@pytest.fixture(name='node_params')
def fixture_node_params(monkeypatch, tmp_path):
    """Set baxter_sim's ~obstacles_file; record its log lines."""
    logs, params = [], {}
    monkeypatch.setattr(rospy, 'get_param', lambda name, default=None: params.get(name, default))
    for level in ('loginfo', 'logerr'):
        monkeypatch.setattr(rospy, level, lambda text, *args, level=level: logs.append(
            (level, text % args)))
    package = package_with_default_file(tmp_path)
    monkeypatch.setattr(rospkg.RosPack, 'get_path', lambda self, name: package)
    return params, logs


@pytest.mark.parametrize('value, words', [
    (3, '~obstacles_file must be a file path'),
    ('/nonexistent/obstacles.yaml', 'cannot read obstacle file /nonexistent/obstacles.yaml'),
])
def test_an_unusable_file_is_logged_and_the_node_runs_without_obstacles(node_params, value,
                                                                       words):
    params, logs = node_params
    params['~obstacles_file'] = value
    assert baxter_params.contacts(DESC, URDF) == {}
    assert len(logs) == 1 and logs[0][0] == 'logerr'
    assert 'running without obstacles' in logs[0][1] and words in logs[0][1]


def test_the_node_takes_the_default_file_unless_told_none(node_params):
    params, logs = node_params
    contacts = baxter_params.contacts(DESC, URDF)
    assert set(contacts) == {'left', 'right'}
    assert logs[-1][0] == 'loginfo' and 'mattress' in logs[-1][1]
    for side, contact in contacts.items():     # the neutral pose is well clear of the bed
        neutral = [bd.neutral_pose(side)[n] for n in bd.arm_joint_names(side)]
        assert contact.guard.clearance(neutral).min() > 0.1
    params['~obstacles_file'] = ''
    assert baxter_params.contacts(DESC, URDF) == {}
    assert logs[-1] == ('loginfo', 'baxter_sim: no obstacles')
