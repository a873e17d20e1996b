"""Our baxter_core_msgs must be wire-identical to Rethink's: same md5sums as the real robot's."""
import pytest

from baxter_core_msgs import msg

# The sums of Rethink's baxter_core_msgs (as `rosmsg md5` prints them for the real SDK).
RETHINK_MD5 = {
    'JointCommand': '19bfec8434dd568ab3c633d187c36f2e',
    'EndEffectorCommand': 'c003234e90416f2ca02ac7837c42cbb7',
    'EndEffectorState': 'ade777f069d738595bc19e246b8ec7a0',
    'EndEffectorProperties': '21b83773ab9a35216d11e427573c76cc',
    'EndpointState': '44bea01d596ff699fa1447bec34167ac',
    'AssemblyState': '356d9dd237ce73b2667da9235f541933',
}


@pytest.mark.parametrize('name', sorted(RETHINK_MD5))
def test_md5sum_matches_rethinks(name):
    assert getattr(msg, name)._md5sum == RETHINK_MD5[name]
