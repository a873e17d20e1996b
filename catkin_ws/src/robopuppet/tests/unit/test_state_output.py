"""Unit tests of robopuppet.protocol.state_output: what serial_X publishes for each event."""
import pytest

from robopuppet import interface, settings
from robopuppet.protocol import codec, state_output as out, state_set

PERIOD_S = 0.02  # a 50 Hz cap of the per-joint topics


def state(start_s, angle_rad=0.5, status=codec.WORKING, button=0):
    joints = tuple(codec.JointState(j, status, angle_rad + 0.125 * j, 0.25 * j)
                   for j in settings.JOINTS)
    return state_set.StateSet(start_s, joints, (0.0, 0.25, 0.5, 1.0), button)


def of_type(outputs, kind):
    return [o for o in outputs if type(o) is kind]


def test_no_joint_topic_before_the_settings_are_loaded_but_grippers_and_button():
    output = out.StateOutput(PERIOD_S)
    outputs = output.on_events([state(1.0, button=2)], 1.01, None)
    assert of_type(outputs, out.JointStates) == of_type(outputs, out.EncStatus) == []
    assert of_type(outputs, out.JointTopics) == []
    assert of_type(outputs, out.Grippers) == [out.Grippers((0.0, 0.25, 0.5, 1.0))]
    assert out.Button(2) in outputs


def test_a_set_begun_before_the_load_finished_is_never_published():
    output = out.StateOutput(PERIOD_S)
    # Its first frame came 10 ms before the load's last write: it may carry angles made with
    # the firmware's defaults (no home offset, no sign).
    outputs = output.on_events([state(9.99)], 10.02, 10.0)
    assert of_type(outputs, out.JointStates) == []
    assert of_type(outputs, out.EncStatus) == of_type(outputs, out.JointTopics) == []
    outputs = output.on_events([state(10.0, angle_rad=0.25)], 10.03, 10.0)
    positions = tuple(0.25 + 0.125 * j for j in settings.JOINTS)
    assert of_type(outputs, out.JointStates) == [
        out.JointStates(positions, tuple(0.25 * j for j in settings.JOINTS))]


def test_enc_stat_at_once_when_it_changes_and_for_every_joint_after_each_load():
    output = out.StateOutput(PERIOD_S)
    first = of_type(output.on_events([state(1.0)], 1.0, 0.5), out.EncStatus)
    assert first == [out.EncStatus(j, interface.WORKING) for j in settings.JOINTS]
    assert of_type(output.on_events([state(1.1)], 1.1, 0.5), out.EncStatus) == []
    changed = of_type(output.on_events([state(1.2, status=codec.UNCALIBRATED)], 1.2, 0.5),
                      out.EncStatus)
    assert changed == [out.EncStatus(j, interface.UNCALIBRATED) for j in settings.JOINTS]
    reloaded = of_type(output.on_events([state(2.0, status=codec.UNCALIBRATED)], 2.0, 1.9),
                       out.EncStatus)
    assert len(reloaded) == settings.NUM_JOINTS


def test_per_joint_topics_are_capped_but_joint_states_are_not():
    output = out.StateOutput(PERIOD_S)
    outputs = []
    for i in range(100):  # 100 Hz for 1 s
        now = 1.0 + i * 0.01
        outputs += output.on_events([state(now)], now, 0.5)
    assert len(of_type(outputs, out.JointStates)) == 100
    # 50 in 1 s, and up to two more: one period of arrival jitter is absorbed at the start.
    assert 48 <= len(of_type(outputs, out.JointTopics)) <= 52
    assert 48 <= len(of_type(outputs, out.Grippers)) <= 52
    topics = of_type(outputs, out.JointTopics)[-1]
    assert topics.angles == pytest.approx([0.5 + 0.125 * j for j in settings.JOINTS])
    assert topics.statuses == (interface.WORKING,) * settings.NUM_JOINTS


def test_a_button_change_is_published_at_once_between_the_capped_ones():
    output = out.StateOutput(1.0)
    for now in (1.0, 1.05):  # the first two: one period of jitter absorbed
        output.on_events([state(now)], now, 0.5)
    quiet = output.on_events([state(1.1)], 1.1, 0.5)
    assert [type(o) for o in quiet] == [out.JointStates]  # no capped topic due
    pressed = output.on_events([state(1.2, button=3)], 1.2, 0.5)
    released = output.on_events([state(1.3, button=0)], 1.3, 0.5)
    assert out.Button(3) in pressed and out.Button(0) in released
    assert of_type(pressed + released, out.Grippers) == []


def test_heartbeats_come_out_in_order_whatever_the_load():
    output = out.StateOutput(PERIOD_S)
    outputs = output.on_events([codec.Heartbeat(), state(1.0), codec.Heartbeat()], 1.0, None)
    assert type(outputs[0]) is out.Heartbeat and type(outputs[-1]) is out.Heartbeat


def test_the_topic_period_must_be_positive():
    with pytest.raises(ValueError):
        out.StateOutput(0.0)


def test_joint_states_carry_the_angle_tag_they_are_given():
    output = out.StateOutput(PERIOD_S)
    outputs = output.on_events([state(1.0)], 1.01, 0.5, 'angle_settings:0123abcd')
    assert [o.angle_tag for o in of_type(outputs, out.JointStates)] == ['angle_settings:0123abcd']
    assert of_type(output.on_events([state(1.1)], 1.11, 0.5), out.JointStates)[0].angle_tag == ''
