"""The ghost description: Baxter's URDF with every link and joint renamed, still a valid tree."""
import shutil
import subprocess
import xml.etree.ElementTree as ET

import pytest

from robopuppet import baxter_description
from robopuppet.ghost import ghost_urdf

ORIGINAL = open(baxter_description.URDF_PATH).read()
GHOST = ghost_urdf.prefix_description(ORIGINAL, 'ghost/')


def names(text):
    """Return ({link names}, {joint names}, [(parent, child, mimic or None) per joint])."""
    root = ET.fromstring(text)
    joints = [(j.find('parent').get('link'), j.find('child').get('link'),
               j.find('mimic').get('joint') if j.find('mimic') is not None else None)
              for j in root.findall('joint')]
    return ({l.get('name') for l in root.findall('link')},
            {j.get('name') for j in root.findall('joint')}, joints)


def test_check_urdf_parses_the_ghost_as_one_tree_rooted_at_the_ghost_base(tmp_path):
    if shutil.which('check_urdf') is None:
        pytest.fail('check_urdf (liburdfdom-tools) is not installed')
    path = tmp_path / 'ghost.urdf'
    path.write_text(GHOST)
    result = subprocess.run(['check_urdf', str(path)], capture_output=True, text=True,
                            timeout=30)
    assert result.returncode == 0, result.stdout + result.stderr
    assert 'root Link: ghost/base' in result.stdout
    assert 'ghost/right_gripper' in result.stdout and 'ghost/left_gripper' in result.stdout


def test_every_link_and_joint_is_prefixed_and_none_is_lost():
    links, joints, _ = names(ORIGINAL)
    ghost_links, ghost_joints, _ = names(GHOST)
    # the whole robot (with the head and hand cameras), not an empty match
    assert len(links) == 33 and len(joints) == 32
    assert ghost_links == {'ghost/' + n for n in links}
    assert ghost_joints == {'ghost/' + n for n in joints}


def test_parents_children_and_mimics_name_the_prefixed_links_and_joints():
    _, _, original = names(ORIGINAL)
    links, joints, ghost = names(GHOST)
    assert ghost == [('ghost/' + p, 'ghost/' + c, m and 'ghost/' + m) for p, c, m in original]
    for parent, child, mimic in ghost:
        assert parent in links and child in links
        assert mimic is None or mimic in joints
    assert sum(1 for *_, m in ghost if m) == 2  # both grippers' mimic fingers


def test_geometry_limits_and_materials_are_unchanged():
    original, ghost = ET.fromstring(ORIGINAL), ET.fromstring(GHOST)
    for tag in ('origin', 'axis', 'limit', 'material', 'color', 'box', 'cylinder', 'sphere'):
        assert [e.attrib for e in original.iter(tag)] == [e.attrib for e in ghost.iter(tag)], tag
        assert len(list(original.iter(tag))) > 0, tag


def test_another_prefix_gives_other_frames():
    links, _, _ = names(ghost_urdf.prefix_description(ORIGINAL, 'preview_'))
    assert 'preview_base' in links and 'ghost/base' not in links


@pytest.mark.parametrize('prefix', ['', '/ghost/', 'gh ost/', None])
def test_a_prefix_that_cannot_start_a_frame_name_is_refused(prefix):
    with pytest.raises(ghost_urdf.PrefixError):
        ghost_urdf.prefix_description(ORIGINAL, prefix)


@pytest.mark.parametrize('text, why', [
    ('<robot name="r"><link name="a"', 'not XML'),
    ('<model><link name="a"/></model>', 'not <robot>'),
    ('<robot name="r"><link name="a"/><gazebo reference="a"/></robot>', 'gazebo'),
    ('<robot name="r"><link/></robot>', 'without name'),
])
def test_text_it_cannot_prefix_is_refused_with_the_reason(text, why):
    with pytest.raises(ghost_urdf.PrefixError, match=why):
        ghost_urdf.prefix_description(text)


def test_the_executable_prints_the_ghost_or_fails_with_a_message(capsys, tmp_path):
    assert ghost_urdf.main([baxter_description.URDF_PATH, 'ghost/']) == 0
    assert names(capsys.readouterr().out)[0] == names(GHOST)[0]
    assert ghost_urdf.main([str(tmp_path / 'missing.urdf')]) == 1
    assert 'missing.urdf' in capsys.readouterr().err
    assert ghost_urdf.main([]) == 2
