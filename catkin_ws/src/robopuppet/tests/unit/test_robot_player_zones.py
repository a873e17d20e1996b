"""Unit tests of which keep-out zones the replay onto the robot keeps (robot_player.keepout_zones):
--zones, else the running arm controllers' zones_file (all of them when they differ), else the
package's; the parameter server is replaced by what it would hold."""
import pytest

from robopuppet import baxter_description
from robopuppet.arm import zone_topics
from robopuppet.episodes import robot_player

SHIPPED = baxter_description.URDF_PATH.replace('urdf/baxter.urdf', 'config/zones.yaml')
SHIPPED_NAMES = ['patient head', 'patient body', 'bed']


@pytest.fixture
def lamp(tmp_path):
    path = tmp_path / 'lamp.yaml'
    path.write_text('frame: base\nshapes:\n  - {name: lamp, type: sphere, radius: 0.1, '
                    'xyz: [0.5, -0.75, 0.45]}\n')
    return str(path)


def chosen(monkeypatch, running, given=None):
    """Return (guards, what it said) with the arm controllers' zones_file as `running`."""
    monkeypatch.setattr(zone_topics, 'controllers_zones_files', lambda: dict(running))
    said = []
    return robot_player.keepout_zones(given, said.append), said


def test_by_default_the_running_arm_controllers_zones(monkeypatch):
    guards, said = chosen(monkeypatch, {'R': SHIPPED})
    assert sorted(guards) == ['left', 'right'] and guards['left'].names == SHIPPED_NAMES
    assert said == ["keep-out zones: %s (3 zones, arm_R's zones_file)" % SHIPPED]


def test_when_the_controllers_differ_the_zones_of_both(monkeypatch, lamp):
    guards, said = chosen(monkeypatch, {'L': lamp, 'R': SHIPPED})
    assert sorted(guards['right'].names) == sorted(SHIPPED_NAMES + ['lamp'])
    assert "(4 zones, arm_L's and arm_R's zones_file differ: the zones of both)" in said[0]
    guards, said = chosen(monkeypatch, {'L': '', 'R': SHIPPED})   # '' : none for arm_L
    assert guards['left'].names == SHIPPED_NAMES and '3 zones' in said[0]


def test_controllers_without_zones_mean_none(monkeypatch):
    assert chosen(monkeypatch, {'L': '', 'R': ''}) == (
        {}, ["keep-out zones: '' (0 zones, arm_L's and arm_R's zones_file)"])


def test_no_arm_controller_the_packages_zones(monkeypatch):
    guards, said = chosen(monkeypatch, {})
    assert guards['right'].names == SHIPPED_NAMES
    assert said[0].endswith("(3 zones, the package's: no arm controller's zones_file is set)")


def test_zones_given_override_the_controllers(monkeypatch, lamp):
    guards, said = chosen(monkeypatch, {'R': SHIPPED}, lamp)
    assert guards['right'].names == ['lamp'] and said == [
        'keep-out zones: %s (1 zone, --zones)' % lamp]
    guards, said = chosen(monkeypatch, {'R': SHIPPED}, '/dev/null')
    assert all(not g.names for g in guards.values()) and '(0 zones, --zones)' in said[0]


def test_a_bad_zone_file_is_refused_naming_file_and_entry(monkeypatch, tmp_path):
    bad = tmp_path / 'bad.yaml'
    bad.write_text('frame: base\nshapes:\n  - {name: head, type: sphere, radius: 0, '
                   'xyz: [0, 0, 0]}\n')
    with pytest.raises(ValueError, match="bad.yaml: shape 'head': radius"):
        chosen(monkeypatch, {'R': SHIPPED}, str(bad))
    with pytest.raises(ValueError, match='bad.yaml'):
        chosen(monkeypatch, {'L': str(bad), 'R': SHIPPED})
