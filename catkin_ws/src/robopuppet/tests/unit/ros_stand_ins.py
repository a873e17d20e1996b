"""Stand-ins for rospy's publishers in unit tests without a ROS master."""
import rospy


class Publisher:
    """Records what goes out on a topic in Publisher.sent, as (topic, message)."""
    sent = []

    def __init__(self, topic, kind, **kwargs):
        self.topic = topic

    def publish(self, msg):
        Publisher.sent.append((self.topic, msg))


def sent_on(topic):
    """Return the messages published on topic, oldest first."""
    return [msg for name, msg in Publisher.sent if name == topic]


def record_publishers(monkeypatch):
    """Make rospy.Publisher a recording Publisher, with nothing sent yet."""
    monkeypatch.setattr(rospy, 'Publisher', Publisher)
    monkeypatch.setattr(Publisher, 'sent', [])
