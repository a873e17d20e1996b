"""Tests of robopuppet.baxter_sim.baxter_topics: Rethink's names, and the tables the node wires."""
import inspect

from roslib.message import get_message_class

from robopuppet import interface
from robopuppet.baxter_sim import baxter_io as bio, baxter_topics as topics
from robopuppet.baxter_sim.baxter_api import BaxterApi


def test_names_are_rethinks():
    assert interface.digital_io_state_topic('left_lower_cuff') == \
        '/robot/digital_io/left_lower_cuff/state'
    assert interface.navigator_state_topic('torso_left') == \
        '/robot/navigators/torso_left_navigator/state'
    assert interface.analog_io_state_topic('right_hand_range') == \
        '/robot/analog_io/right_hand_range/state'
    assert interface.ik_service('right') == '/ExternalTools/right/PositionKinematicsNode/IKService'


def test_every_io_component_and_the_head_publish_once_with_a_known_type():
    published = topics.io_publications()
    names = [topic for topic, _ in published]
    assert len(names) == len(set(names)) == (
        len(bio.DIGITAL_INPUTS + bio.DIGITAL_OUTPUTS + bio.NAVIGATORS + bio.ANALOG_INPUTS
            + bio.ANALOG_OUTPUTS) + 1 + 2)   # + the head, each arm's collision avoidance
    assert all(get_message_class(kind) is not None for _, kind in published)
    assert (interface.HEAD_STATE, 'baxter_core_msgs/HeadState') in published
    assert ('/robot/limb/left/collision_avoidance_state',
            'baxter_core_msgs/CollisionAvoidanceState') in published


def test_each_subscription_feeds_a_method_the_arguments_it_takes():
    rows = topics.subscriptions()
    # 9 robot topics (+ publish rate); per arm 4 + feed-forward, rsdk x2, suppress x2
    assert len({row.topic for row in rows}) == len(rows) == 9 + 2 * 9
    for row in rows:
        kind = get_message_class(row.kind)
        assert set(row.fields) <= set(kind.__slots__), row.topic
        taken = list(inspect.signature(getattr(BaxterApi, row.method)).parameters)[1:]
        given = (['topic'] + ['side'] * (row.side is not None) + list(row.fields)
                 + ['now_s'] * row.timed + ['wall_s'])
        assert len(taken) == len(given) and taken[-1] == 'wall_s', row.topic
