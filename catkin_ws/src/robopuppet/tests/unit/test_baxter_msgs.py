"""Our baxter_core_msgs must be wire-identical to Rethink's: same md5sums as the real robot's."""
import pytest

from baxter_core_msgs import msg, srv

# The sums of Rethink's baxter_core_msgs 1.2 (as `rosmsg md5` prints them for the real SDK; the
# newer ones also appear in rosserial's and roslisp's generated code of the real package).
RETHINK_MD5 = {
    'JointCommand': '19bfec8434dd568ab3c633d187c36f2e',
    'EndEffectorCommand': 'c003234e90416f2ca02ac7837c42cbb7',
    'EndEffectorState': 'ade777f069d738595bc19e246b8ec7a0',
    'EndEffectorProperties': '21b83773ab9a35216d11e427573c76cc',
    'EndpointState': '44bea01d596ff699fa1447bec34167ac',
    'AssemblyState': '356d9dd237ce73b2667da9235f541933',
    'DigitalIOState': '29d0be3859dae81a66b28f167ecec98c',
    'DigitalOutputCommand': '23f05028c1a699fb83e22401228c3a9e',
    'HeadState': '71c43b264307205358e7e49be5601348',
    'HeadPanCommand': '23b8a3f4b7ee9de7099d029e57660a8c',
    'NavigatorState': '626a2401ea06bafc2f1ecf16d05f1675',
    'AnalogIOState': '39af371963dc9e4447e91f430c720b33',
}
# SolvePositionIK (SDK 1.2: with seed_angles, seed_mode and result_type): request, response.
RETHINK_SRV_MD5 = {
    'SolvePositionIKRequest': '2587e42983d0081d0a2288230991073b',
    'SolvePositionIKResponse': 'd9b0c2b3932e08421f5094cf62743b9f',
}


@pytest.mark.parametrize('name', sorted(RETHINK_MD5))
def test_md5sum_matches_rethinks(name):
    assert getattr(msg, name)._md5sum == RETHINK_MD5[name]


@pytest.mark.parametrize('name', sorted(RETHINK_SRV_MD5))
def test_service_md5sum_matches_rethinks(name):
    assert getattr(srv, name)._md5sum == RETHINK_SRV_MD5[name]
