"""robopuppet.arm.arm_params: arm_X's ~parameters checked, told and made into its controller
(rospy's parameter server and log replaced; no ROS master)."""
import pytest
import rospy

from robopuppet import interface
from robopuppet.arm import arm_params, controller
from robopuppet.periodic import Guard


@pytest.fixture
def node(monkeypatch):
    """Return (params {~name: value}, log lines [(level, text)]) that make_controller sees."""
    params, lines = {}, []
    monkeypatch.setattr(rospy, 'get_param', lambda name, default=None: params.get(name, default))
    for level in ('loginfo', 'logwarn'):
        monkeypatch.setattr(rospy, level, lambda text, *args, level=level: lines.append(
            (level, text % args)))
    return params, lines


def make():
    return arm_params.make_controller('R', Guard('arm_R', print), 'arm_R')


def test_the_defaults_make_a_controller_at_100_hz_and_say_so(node):
    _, lines = node
    core, period_s, zones = make()
    assert isinstance(core, controller.ArmController) and zones == []
    assert period_s == pytest.approx(0.01) and core.command_period_s == pytest.approx(0.01)
    assert core.timing.timeout_s == pytest.approx(0.4)
    assert core.link.bound.bound_s == pytest.approx(0.35)
    assert [level for level, _ in lines] == ['loginfo'] * 3
    assert lines[-1] == ('loginfo', 'arm_R: 0 keep-out zones (~zones_file is empty)')


def test_a_comm_rate_too_low_to_stop_in_time_is_a_warning(node):
    params, lines = node
    params['~comm_rate'] = 2.0
    make()
    assert lines[0][0] == 'logwarn' and 'only after 2.10 s' in lines[0][1]


@pytest.mark.parametrize('name, value', [('~command_rate', 5.0), ('~approach_speed', 0.0),
                                         ('~max_sample_age', True), ('~comm_rate', 'fast')])
def test_a_bad_parameter_stops_the_node_naming_it(node, name, value):
    params, _ = node
    params[name] = value
    with pytest.raises(ValueError, match=name):
        make()


def test_the_heartbeat_timeout_reaches_the_puppet_watch(node):
    params, _ = node
    params['~heartbeat_timeout'] = 1.5
    core, _, _ = make()
    assert core.teleop.puppet.heartbeat_timeout_s == 1.5
    assert interface.HEARTBEAT_TIMEOUT_S != 1.5


def test_the_leash_is_on_by_default_and_0_turns_it_off(node):
    params, _ = node
    assert make()[0].teleop.drive.leash_s == pytest.approx(0.1)
    params['~leash'] = 0
    assert make()[0].teleop.drive.leash_s == 0.0
    params['~leash'] = 0.05
    assert make()[0].teleop.drive.leash_s == pytest.approx(0.05)


@pytest.mark.parametrize('value', [-0.1, float('nan'), float('inf'), False, 'short'])
def test_a_negative_or_non_finite_leash_stops_the_node(node, value):
    params, _ = node
    params['~leash'] = value
    with pytest.raises(ValueError, match='~leash'):
        make()
