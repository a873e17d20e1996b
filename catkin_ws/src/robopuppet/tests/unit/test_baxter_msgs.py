"""Our baxter_core_msgs must be wire-identical to Rethink's: same md5sums as the real robot's."""
import io
import pathlib

import pytest

from baxter_core_msgs import msg, srv

from robopuppet.baxter_sim import baxter_io

# Rethink's baxter_common at tag 1.2.0 (commit 6c4b0f375fe4e356a3b12df26ef7c0d5e58df86e): the
# md5sums genmsg computes from its msg/srv text (SDK 1.2.0, what a real Baxter speaks).
RETHINK_MD5 = {
    'AnalogIOState': '39af371963dc9e4447e91f430c720b33',
    'AnalogOutputCommand': 'a7b945129a083ca4095d48aa94841d85',
    'AssemblyState': '356d9dd237ce73b2667da9235f541933',
    'CameraControl': '01e38dd67dfb36af457f0915248629d1',
    'CameraSettings': 'd133bef4a3bd9a6e490a5dc91d20f429',
    'CloseCamera': '1067b4a7f008fe1ff4bd9668312773fd',
    'CloseCameraRequest': 'c1f3d28f1b044c871e6eff2e9fc3c667',
    'CloseCameraResponse': 'b6e094011a4dfaee5eddf447220446cf',
    'CollisionAvoidanceState': '30f5cb8ae019f1ffe8b599e6d2e589c7',
    'DigitalIOState': '29d0be3859dae81a66b28f167ecec98c',
    'DigitalOutputCommand': '23f05028c1a699fb83e22401228c3a9e',
    'EndEffectorCommand': 'c003234e90416f2ca02ac7837c42cbb7',
    'EndEffectorProperties': '21b83773ab9a35216d11e427573c76cc',
    'EndEffectorState': 'ade777f069d738595bc19e246b8ec7a0',
    'EndpointState': '44bea01d596ff699fa1447bec34167ac',
    'HeadPanCommand': '23b8a3f4b7ee9de7099d029e57660a8c',
    'HeadState': '71c43b264307205358e7e49be5601348',
    'JointCommand': '19bfec8434dd568ab3c633d187c36f2e',
    'ListCameras': '855b31192ab61744e7deb992d94db7ff',
    'ListCamerasRequest': 'd41d8cd98f00b204e9800998ecf8427e',
    'ListCamerasResponse': '855b31192ab61744e7deb992d94db7ff',
    'NavigatorState': '680d121a1f16a32647298b292492fffd',
    'OpenCamera': '73eacff63d5f9cca2d986614515a5c8c',
    'OpenCameraRequest': 'c4194eee32741c5a98ef8da9666fa6c9',
    'OpenCameraResponse': 'b6e094011a4dfaee5eddf447220446cf',
    'SolvePositionIK': '18cc92fd96853eb10b34de0b5c7d3cba',
    'SolvePositionIKRequest': '2587e42983d0081d0a2288230991073b',
    'SolvePositionIKResponse': 'd9b0c2b3932e08421f5094cf62743b9f',
}


@pytest.mark.parametrize('name', sorted(RETHINK_MD5))
def test_md5sum_matches_rethinks(name):
    kind = getattr(msg, name, None) or getattr(srv, name)
    assert kind._md5sum == RETHINK_MD5[name]


def test_the_stand_ins_navigator_states_are_navigator_state_messages():
    for fields in baxter_io.DigitalIO().navigator_states().values():
        assert sorted(fields) == sorted(msg.NavigatorState.__slots__)
        msg.NavigatorState(**fields).serialize(io.BytesIO())


def test_every_message_and_service_of_the_subset_is_pinned():
    package = pathlib.Path(__file__).resolve().parents[3] / 'baxter_core_msgs'
    names = {path.stem for folder in ('msg', 'srv') for path in (package / folder).iterdir()}
    services = {path.stem for path in (package / 'srv').iterdir()}
    names |= {name + part for name in services for part in ('Request', 'Response')}
    assert names == set(RETHINK_MD5)
