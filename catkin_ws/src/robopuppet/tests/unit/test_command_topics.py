"""command_topics: what the GUI publishes to command a puppet arm (publishers faked)."""
import types

import pytest

from robopuppet.gui import state
from robopuppet.gui.command_topics import CommandTopics


@pytest.mark.parametrize('mode, first', [('hold', [('setpoint', 2, 0.4)]),
                                         ('feel', [('setpoint', 2, 0.4)]), ('limp', [])])
def test_the_client_sends_the_current_angles_before_hold_and_feel(mode, first):
    sent = []
    fake = types.SimpleNamespace(
        state=state.ArmState(), set_setpoint=lambda j, a: sent.append(('setpoint', j, a)),
        _opmode_pub=types.SimpleNamespace(publish=lambda msg: sent.append(('opmode', msg.data))))
    fake.state.on_angle(2, 0.4, 1.0)  # the other joints' angles are unknown: no setpoint
    CommandTopics.set_opmode(fake, mode)
    assert sent == first + [('opmode', mode)]


def test_an_unknown_opmode_is_refused():
    fake = types.SimpleNamespace(state=state.ArmState())
    with pytest.raises(ValueError, match='opmode must be one of'):
        CommandTopics.set_opmode(fake, 'dance')
