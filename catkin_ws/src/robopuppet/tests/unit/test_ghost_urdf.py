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


def colours(text):
    """Return {material name: (r, g, b, a)} of a description's top-level materials."""
    return {m.get('name'): tuple(float(c) for c in m.find('color').get('rgba').split())
            for m in ET.fromstring(text).findall('material')}


@pytest.mark.parametrize('name', sorted(ghost_urdf.TINTS))
def test_the_ghost_and_the_target_are_tinted_and_pass_check_urdf(tmp_path, name):
    tint = ghost_urdf.TINTS[name]
    text = ghost_urdf.prefix_description(ORIGINAL, name + '/', tint)
    original, tinted = colours(ORIGINAL), colours(text)
    assert set(tinted) == set(original) and len(original) >= 7
    for material, (r, g, b, a) in tinted.items():
        assert a == original[material][3]
        scale = r / tint[0]   # every colour is the tint, shaded
        assert (g, b) == (pytest.approx(tint[1] * scale, abs=2e-3),
                          pytest.approx(tint[2] * scale, abs=2e-3)), material
        assert ghost_urdf.SHADE_FLOOR - 0.01 <= scale <= 1.0
    # Baxter's dark joints stay darker than its light grey parts
    assert tinted['baxter_black'][0] < tinted['baxter_grey'][0]
    # visuals name the materials, so RViz draws every link in the tint
    assert {m.get('name') for m in ET.fromstring(text).iter('material')} == set(original)
    path = tmp_path / 'tinted.urdf'
    path.write_text(text)
    result = subprocess.run(['check_urdf', str(path)], capture_output=True, text=True,
                            timeout=30)
    assert result.returncode == 0, result.stdout + result.stderr
    assert 'root Link: %s/base' % name in result.stdout


def test_ghost_and_target_tints_differ_from_each_other_and_from_baxters_red():
    ghost, target = (colours(ghost_urdf.prefix_description(ORIGINAL, 'x/', ghost_urdf.TINTS[n]))
                     for n in ('ghost', 'target'))
    red = colours(ORIGINAL)['baxter_red']
    assert red[0] > 0.5 and red[2] < 0.1
    assert ghost['baxter_red'][2] > ghost['baxter_red'][0] + 0.3     # blue
    assert target['baxter_red'][1] > target['baxter_red'][0] + 0.3   # green


def test_the_launch_file_asks_for_the_tints_by_name():
    launch = open(baxter_description.URDF_PATH.replace('urdf/baxter.urdf',
                                                       'launch/ghost.launch')).read()
    assert '$(arg ghost_prefix) ghost"' in launch and '$(arg target_prefix) target"' in launch


def test_the_command_prints_a_tinted_description(tmp_path, capsys):
    assert ghost_urdf.main([baxter_description.URDF_PATH, 'target/', 'target']) == 0
    assert colours(capsys.readouterr().out) == colours(ghost_urdf.prefix_description(
        ORIGINAL, 'target/', ghost_urdf.TINTS['target']))
    assert ghost_urdf.main([baxter_description.URDF_PATH, 'g/', '0.1,0.2,0.9']) == 0
    assert colours(capsys.readouterr().out)['baxter_grey'][2] > 0.5
    assert ghost_urdf.main([baxter_description.URDF_PATH, 'g/', 'purple']) == 1
    assert 'tint' in capsys.readouterr().err
