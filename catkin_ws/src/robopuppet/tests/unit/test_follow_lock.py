"""robopuppet.config.follow_lock: when config_X refuses a change of what the puppet's angles
mean (an arm follows, by the newest teleop_state) and what it tells the operator."""
import pytest

from robopuppet.config import follow_lock


@pytest.mark.parametrize('left, right, text', [
    (False, False, ''),
    (False, True, "Baxter's right arm follows this puppet: stop following first: press 3"),
    (True, False, "Baxter's left arm follows this puppet: stop following first: press 2"),
    (True, True, "Baxter's left and right arms follow this puppet: stop following first: "
                 'press 2 and 3'),
])
def test_the_text_names_the_following_arms_and_their_buttons(left, right, text):
    assert follow_lock.following(left, right) == text


def test_the_newest_teleop_state_locks_until_it_is_stale():
    lock = follow_lock.FollowLock()
    assert lock.why(0.0) == ''   # never heard from arm_X
    lock.on_teleop_state(1.0, False, True)
    assert lock.why(1.0) == lock.why(1.0 + follow_lock.TELEOP_STALE_S) == (
        follow_lock.following(False, True))
    assert lock.why(1.01 + follow_lock.TELEOP_STALE_S) == ''   # arm_X silent: it stops itself
    lock.on_teleop_state(5.0, False, False)
    assert lock.why(5.0) == ''
