"""Shape files (world.shapes, world.zones): the shipped zones, URDF link shapes, refusals."""
import os

import numpy as np
import pytest

from robopuppet import baxter_description as bd
from robopuppet.cameras import scene
from robopuppet.world import shapes, zones

CONFIG = os.path.join(os.path.dirname(bd.URDF_PATH), '..', 'config')


def test_the_shipped_zones_cover_the_simulated_patient_with_a_margin():
    found = {z.name: z for z in zones.load_zones(os.path.join(CONFIG, 'zones.yaml'))}
    world = {s.name: s for s in scene.load_world(os.path.join(CONFIG, 'world.yaml')).shapes}
    assert {'patient head', 'patient body', 'bed'} <= set(found)
    head, zone = world['patient_head'], found['patient head']
    gap = zone.radius - head.radius - np.linalg.norm(np.subtract(zone.xyz, head.xyz))
    assert gap >= 0.05
    body = found['patient body']
    low = np.subtract(body.xyz, np.array(body.size) / 2.0)
    high = np.add(body.xyz, np.array(body.size) / 2.0)
    for name in ('patient_torso', 'blanket_over_legs'):
        part = world[name]
        assert (low + 0.03 <= np.subtract(part.xyz, np.array(part.size) / 2.0)).all()
        assert (np.add(part.xyz, np.array(part.size) / 2.0) <= high - 0.03).all()


def test_an_empty_zone_file_has_no_zones(tmp_path):
    path = tmp_path / 'zones.yaml'
    path.write_text('# nothing\n')
    assert zones.load_zones(str(path)) == []


@pytest.mark.parametrize('text, words', [
    ('shapes: [{name: wall, type: cone, radius: 1, xyz: [0, 0, 0]}]',
     "shape 'wall': type must be one of"),
    ('shapes: [{name: wall, type: box, xyz: [0, 0, 0]}]', "'wall' \\(box\\) needs size"),
    ('shapes: [{name: head, type: sphere, radius: 0, xyz: [0, 0, 0]}]',
     "'head': radius must be a positive number"),
    ('shapes: [{name: a, type: sphere, radius: 1, xyz: [0, 0]}]', "'a': xyz must be a list"),
    ('frame: world\nshapes: []', "in Baxter's 'base' frame"),
    ('floor: {z: 0}', "unknown keys \\['floor'\\]"),
    ('shapes: [', 'is not YAML'),
    ('- a list', 'must be a mapping'),
])
def test_a_bad_zone_file_is_refused_naming_file_and_entry(tmp_path, text, words):
    path = tmp_path / 'bad_zones.yaml'
    path.write_text(text)
    with pytest.raises(zones.ZoneFileError, match=words) as caught:
        zones.load_zones(str(path))
    assert str(path) in str(caught.value)
    assert isinstance(caught.value, ValueError)
    assert isinstance(caught.value, shapes.ShapeFileError)


def test_a_missing_zone_file_is_refused_naming_it(tmp_path):
    with pytest.raises(zones.ZoneFileError, match='cannot read zone file .*none.yaml'):
        zones.load_zones(str(tmp_path / 'none.yaml'))


LINKS_URDF = """<robot name="r">
  <material name="grey"><color rgba="0.5 0.5 0.5 1"/></material>
  <link name="both">
    <collision><geometry><cylinder radius="0.1" length="0.4"/></geometry></collision>
    <visual><origin xyz="0 0 0.2" rpy="0 0 1.5"/><geometry><box size="1 2 3"/></geometry>
      <material name="grey"/></visual>
  </link>
  <link name="seen">
    <visual><geometry><mesh filename="package://r/a.dae"/></geometry></visual>
    <visual><origin xyz="1 2 3"/><geometry><sphere radius="0.2"/></geometry>
      <material name="red"><color rgba="1 0 0 1"/></material></visual>
  </link>
  <link name="mesh_only">
    <visual><geometry><mesh filename="package://r/b.dae"/></geometry></visual>
  </link>
</robot>"""


def test_a_urdfs_links_become_shapes_of_the_first_tag_they_have():
    first = shapes.link_shapes(LINKS_URDF, ('collision', 'visual'))
    assert first == {
        'both': [shapes.Shape('both', 'cylinder', None, 0.1, 0.4, (0.0,) * 3, (0.0,) * 3, None)],
        'seen': [shapes.Shape('seen', 'sphere', None, 0.2, None, (1.0, 2.0, 3.0), (0.0,) * 3,
                              (1.0, 0.0, 0.0))]}
    visual = shapes.link_shapes(LINKS_URDF, ('visual',))
    assert visual['both'] == [shapes.Shape('both', 'box', (1.0, 2.0, 3.0), None, None,
                                           (0.0, 0.0, 0.2), (0.0, 0.0, 1.5), (0.5, 0.5, 0.5))]


@pytest.mark.parametrize('text, words', [
    ('<robot', 'not XML'),
    ('<robot><link name="l"><visual/></link></robot>', "link 'l': <visual> without <geometry>"),
    ('<robot><link name="l"><visual><geometry/></visual></link></robot>', 'empty <geometry>'),
    ('<robot><link name="l"><visual><geometry><cone/></geometry></visual></link></robot>',
     'unknown geometry <cone>'),
    ('<robot><link name="l"><visual><geometry><box size="1 2"/></geometry></visual></link>'
     '</robot>', "link 'l': expected 3 numbers"),
])
def test_a_bad_urdf_shape_is_refused_naming_its_link(text, words):
    with pytest.raises(shapes.ShapeFileError, match=words):
        shapes.link_shapes(text, ('visual',))
