"""robopuppet.arm.angle_settings and settings.angle_tag: which stored settings change what the
puppet's angles mean, and arm_X's refusal of samples made with other angle settings, whichever
of stored_settings and the samples arrives first (fed to the controller as the node feeds it,
see test_controller.Rig)."""
import pytest

from robopuppet import interface, settings
from robopuppet.arm import controller
from robopuppet.arm.angle_settings import AngleSettingsWatch, describe
from test_controller import POSE, Rig

STORED = [dict(settings.DEFAULTS, home_angle=0.1 * j) for j in settings.JOINTS]
OTHERS = [n for n in settings.NAMES if n not in settings.ANGLE_SETTINGS]


def joints(values=STORED, **changed):
    """Return [(joint, {name: value})] of values, with changed {'name_J': value} laid over."""
    out = [(j, dict(v)) for j, v in enumerate(values)]
    for key, value in changed.items():
        name, joint = key.rsplit('_', 1)
        out[int(joint)][1][name] = value
    return out


def test_the_angle_settings_are_those_the_firmware_computes_the_reported_angle_with():
    assert set(settings.ANGLE_SETTINGS) == {'home_angle', 'sign_angle', 'angle_min',
                                            'angle_max', 'velocity_min', 'velocity_max'}
    assert set(OTHERS) == {'voltage_min', 'voltage_max', 'pid_kp', 'pid_ki', 'pid_kd',
                           'sign_motor'}


def test_the_tag_names_the_angle_settings_as_float32_values():
    tag = settings.angle_tag(STORED)
    assert tag.startswith(settings.ANGLE_TAG_PREFIX)
    assert settings.angle_tag([dict(v) for v in STORED]) == tag
    for name in OTHERS:   # a gain or a voltage limit is not in it
        assert settings.angle_tag([dict(v, **{name: 3.0}) for v in STORED]) == tag
    for name in settings.ANGLE_SETTINGS:
        changed = [dict(v) for v in STORED]
        changed[6][name] = -changed[6][name] if changed[6][name] else 0.25
        assert settings.angle_tag(changed) != tag, name
    # as float32: a double that rounds to the same float32 is the same setting
    assert settings.angle_tag([dict(v, home_angle=0.1) for v in STORED]) == settings.angle_tag(
        [dict(v, home_angle=0.1 + 1e-12) for v in STORED])


def test_the_first_stored_settings_are_no_change_and_each_angle_setting_is_one():
    watch = AngleSettingsWatch()
    assert watch.on_stored(joints()) == []
    assert watch.tag == settings.angle_tag(STORED)
    assert watch.on_stored(joints()) == []   # the same again (a reconnect, config_X restarted)
    for name in OTHERS:
        assert watch.on_stored(joints(**{name + '_3': 2.0})) == []
    assert watch.on_stored(joints(home_angle_0=0.5)) == [(0, 'home_angle')]
    assert watch.on_stored(joints(home_angle_0=0.5, sign_angle_2=-1.0, angle_max_2=1.0)) == [
        (2, 'angle_max'), (2, 'sign_angle')]
    assert watch.on_stored(joints(home_angle_0=0.5, sign_angle_2=-1.0, angle_max_2=1.0,
                                  velocity_min_6=-1.0)) == [(6, 'velocity_min')]


def test_stored_settings_without_every_joint_or_angle_setting_change_nothing():
    watch = AngleSettingsWatch()
    watch.on_stored(joints())
    tag = watch.tag
    for bad in (joints()[:6], joints() + joints()[:1], [(j + 1, v) for j, v in joints()],
                [(0, {'pid_kp': 1.0})] + joints()[1:]):
        with pytest.raises(ValueError):
            watch.on_stored(bad)
    assert watch.tag == tag
    assert watch.on_stored(joints()) == []


def test_a_sample_is_followed_only_with_the_tag_of_the_newest_stored_settings():
    watch = AngleSettingsWatch()
    tag = settings.angle_tag(STORED)
    assert watch.refusal('') == ''   # untagged: a test or a tool
    assert 'before' in watch.refusal(tag)   # no stored settings known yet
    watch.on_stored(joints())
    assert watch.refusal(tag) == ''
    assert 'other angle settings' in watch.refusal(settings.angle_tag(
        [dict(v, home_angle=0.5) for v in STORED]))
    assert 'other angle settings' in watch.refusal('garbage')
    assert watch.refused == 3


def test_changes_are_described_joint_by_joint():
    assert describe([(0, 'home_angle')]) == "joint 0's home_angle"
    assert describe([(2, 'sign_angle'), (0, 'home_angle'), (2, 'home_angle')]) == (
        "joint 0's home_angle, joint 2's sign_angle and home_angle")


# ---- arm_X: the controller, fed as the node feeds it --------------------------------------

class TaggedRig(Rig):
    """A Rig whose puppet samples carry a tag, as serial_X's do."""

    def __init__(self):
        super().__init__()
        self.tag = settings.angle_tag(STORED)

    def puppet(self, statuses=interface.WORKING, angles=None, age_s=0.0):
        for joint in settings.JOINTS:
            self.core.on_status(joint, statuses)
        self.core.on_heartbeat(self.t)
        return self.core.on_joint_states(self.t, settings.JOINT_NAMES, angles or POSE['right'],
                                         self.operator_s(age_s), self.now_s(), self.tag)


def arm_commands(actions):
    return [a.angles for a in actions if isinstance(a, controller.ArmCommand)]


def following_rig():
    rig = TaggedRig()
    assert rig.core.on_stored_settings(joints()) == ''
    rig.step()
    assert rig.core.teleop.state == interface.READY
    rig.press(interface.BUTTON_RIGHT)
    assert rig.core.teleop.following['right']
    return rig


def test_tagged_samples_wait_for_the_stored_settings():
    rig = TaggedRig()
    for _ in range(5):
        rig.step()
    assert rig.core.teleop.state == interface.CALIBRATING
    assert "before config_X's stored settings came" in rig.core.teleop.detail
    rig.core.on_stored_settings(joints())
    rig.step()
    assert rig.core.teleop.state == interface.READY


def test_the_device_first_samples_of_the_new_meaning_are_refused_until_stored_settings_come():
    rig = following_rig()
    before = arm_commands(rig.step())[-1]
    jumped = list(POSE['right'])
    jumped[0] -= 0.5   # home_angle 0.5 rad up: the reported angle jumps down
    rig.tag = settings.angle_tag([dict(v, home_angle=0.5) if j == 0 else v
                                  for j, v in enumerate(STORED)])
    for _ in range(20):   # 0.2 s of new-meaning samples before stored_settings
        for command in arm_commands(rig.step(angles=jumped)):
            assert command == pytest.approx(before, abs=1e-9)   # Baxter stays
    assert rig.core.teleop.state == interface.FOLLOWING   # not silent yet (0.4 s)
    assert dict(rig.core._report(rig.t + 1.0).values)['refused_for_angle_settings'] == '20'
    assert rig.core.on_stored_settings(joints(home_angle_0=0.5)) == (
        "joint 0's home_angle changed in stored_settings: following stops")
    out = rig.step(angles=jumped)
    assert arm_commands(out) == [pytest.approx(POSE['right'])]   # stay where Baxter is
    tp = rig.core.teleop
    assert (tp.state, tp.following['right']) == (interface.READY, False)
    assert tp.detail == ("joint 0's home_angle changed: following stopped; press 3 to follow "
                         'again')
    assert not any(arm_commands(rig.step(angles=jumped)) for _ in range(50))   # nothing more
    rig.core.on_button(interface.BUTTON_RIGHT)   # a new press approaches slowly (0.5 rad/s)
    rig.step(angles=jumped)
    rig.core.on_button(0)
    assert tp.following['right'] and not tp.tracking['right']
    shoulder = [arm_commands(rig.step(angles=jumped))[0][0] for _ in range(50)]
    for k, command in enumerate(shoulder):   # over T s at most 0.5 x (T + 10 ms)
        assert POSE['right'][0] - command <= 0.5 * (0.01 * (k + 1) + 0.02) + 1e-9
    assert POSE['right'][0] - shoulder[-1] == pytest.approx(0.25, abs=0.02)


def test_stored_settings_first_refuses_the_old_meaning_until_the_device_has_the_new_one():
    rig = following_rig()
    rig.core.on_stored_settings(joints(sign_angle_2=-1.0))
    out = rig.step()   # still the old tag: refused, and following stops
    assert arm_commands(out) == [pytest.approx(POSE['right'])]
    assert rig.core.teleop.detail.startswith("joint 2's sign_angle changed")
    rig.tag = settings.angle_tag([dict(v, sign_angle=-1.0) if j == 2 else v
                                  for j, v in enumerate(STORED)])
    rig.step()
    assert rig.core.teleop.state == interface.READY


def test_new_meaning_samples_with_no_stored_settings_end_in_a_fault_never_followed():
    rig = following_rig()
    rig.tag = 'angle_settings:00000000'
    for _ in range(60):
        out = rig.step(angles=[a + 0.5 for a in POSE['right']])
        assert all(c == pytest.approx(POSE['right']) for c in arm_commands(out))
    tp = rig.core.teleop
    assert tp.state == interface.FAULT and 'other angle settings' in tp.detail


def test_a_settings_change_of_gains_or_while_not_following_changes_nothing():
    rig = following_rig()
    assert rig.core.on_stored_settings(joints(pid_kp_1=5.0)) == ''
    rig.step()
    assert rig.core.teleop.following['right']
    rig.press(interface.BUTTON_RIGHT)
    detail = rig.core.teleop.detail
    assert rig.core.on_stored_settings(joints(home_angle_1=1.0)) != ''
    rig.tag = settings.angle_tag([dict(v, home_angle=1.0) if j == 1 else v
                                  for j, v in enumerate(STORED)])
    rig.step()
    assert rig.core.teleop.detail == detail   # nothing followed: nothing to say
    assert rig.core.on_stored_settings(joints()[:3]).startswith('stored_settings ignored')
