"""Unit tests of the calibrate command's dialog (calibration.dialog) against a fake arm: the
joints to turn, each pose captured as the puppet reports it, then stored, refused or not."""
import types

from robopuppet import interface, settings
from robopuppet.calibration import dialog, procedure

HOME = (0.1, -0.2, 0.0, 0.3, 0.05, -0.1, 0.2)  # what the solver should find


class FakeArm:
    """An arm whose reported angles follow the pose shown (true home HOME, sign +1, stored
    home 0): as if the operator posed the puppet so before each Enter."""

    side = 'R'

    def __init__(self, status=interface.WORKING, sim=False):
        self.status, self.sim, self.pose, self.shown, self.stores = status, sim, None, [], []
        self.posed = []
        self._stored = {j: dict(settings.DEFAULTS, home_angle=0.0, sign_angle=1.0)
                        for j in settings.JOINTS}

    def readings(self):
        angles = self.pose.angles_rad if self.pose is not None else (0.0,) * 7
        return [(self.status, a + h) for a, h in zip(angles, HOME)], self._stored

    def show_target(self, pose):
        self.pose = pose
        self.shown.append(pose and pose.name)

    def sim_running(self):
        return self.sim

    def pose_sim(self, angles_rad):
        self.posed.append(tuple(angles_rad))

    def set_arm_config(self, values):
        self.stores.append(values)
        return types.SimpleNamespace(stored=True, error='')


def converse(arm, answers, assume_yes=False, dry_run=False):
    """Return (exit status, what was said, the prompts) with the operator typing answers."""
    said, prompts, answers = [], [], list(answers)

    def ask(text):
        prompts.append(text)
        return answers.pop(0)
    status = dialog.converse(arm, assume_yes, dry_run, ask=ask,
                             ask_live=lambda text, live: ask(text), say=said.append)
    return status, said, prompts


def test_every_pose_captured_then_stored_after_a_yes():
    arm = FakeArm()
    status, said, prompts = converse(arm, ['', '', '', 'y'])
    assert status == 0
    assert arm.shown == [p.name for p in procedure.POSES] + [None]
    [stored] = arm.stores
    assert [round(stored[j]['home_angle'], 6) for j in settings.JOINTS] == list(HOME)
    assert said[-1] == 'stored joints %s' % list(settings.JOINTS)
    assert prompts[-1] == 'Store the new values? [y/N] '


def test_a_dry_run_and_a_no_store_nothing():
    for answers, dry_run, expected in ((['', '', ''], True, 0), (['', '', '', 'n'], False, 1)):
        arm = FakeArm()
        status, said, _ = converse(arm, answers, dry_run=dry_run)
        assert (status, said[-1], arm.stores) == (expected, 'Nothing stored.', [])


def test_quit_retake_and_the_virtual_puppet():
    arm = FakeArm(sim=True)
    status, said, prompts = converse(arm, ['', 'r', 'p', 'q'])
    assert status == 1
    assert arm.shown == ["Baxter's zero pose", 'pose A', "Baxter's zero pose",
                         "Baxter's zero pose"]
    assert arm.posed == [procedure.POSES[0].angles_rad]
    assert 'p: pose the virtual puppet' in prompts[0]
    assert ("the virtual puppet moves to Baxter's zero pose: press Enter once it is there"
            in said)


def test_joints_not_working_are_turned_first():
    arm = FakeArm(status=interface.UNCALIBRATED)
    status, _, prompts = converse(arm, ['q'])
    assert status == 1
    assert prompts == ['Turn joints %s through their index mark (0 rad), then press Enter: '
                       % list(settings.QUAD_JOINTS)]
