"""Subscriptions across the operator-robot link that come back within a second of its return.

rospy's own take up to 25 s after a long cut (docs/remote.md, "After a cut"). A LinkRecovery
watches its node's subscriptions to publishers never quiet for long. When one has received
nothing for SILENT_S after it had received something, it asks the publisher's node for its pid
over a new connection (one without TCP's backoff) every PROBE_PERIOD_S; once the node answers,
every connection of this node to a publisher on that host is made anew through ROS's own slave
API (publisherUpdate); a reconnection that brings nothing is tried again a few times, and a
publisher quiet of its own accord costs only those (link_silence.StuckConnections). connections() reads rospy 1.15's internals: rospy has no public API for them.
"""
import threading
import time
import xmlrpc.client

import rospy
from rospy.impl.registration import get_topic_manager

from robopuppet.link_silence import StuckConnections, host_of
from robopuppet.periodic import Guard, Loop

PROBE_PERIOD_S = 0.25   # how often a silent connection's publisher is asked, and the check runs
PROBE_TIMEOUT_S = 0.5   # a probe without an answer within this: the link is still down


class _TimeoutTransport(xmlrpc.client.Transport):
    def __init__(self, timeout_s):
        super().__init__()
        self._timeout_s = timeout_s

    def make_connection(self, host):
        connection = super().make_connection(host)
        connection.timeout = self._timeout_s
        return connection


def answers(uri, timeout_s=PROBE_TIMEOUT_S):
    """Return whether the ROS node at uri answers getPid within timeout_s (a new connection)."""
    try:
        proxy = xmlrpc.client.ServerProxy(uri, transport=_TimeoutTransport(timeout_s))
        code, _, _ = proxy.getPid(rospy.get_name())
        return code == 1
    except (OSError, xmlrpc.client.Error, ValueError):
        return False


def connections(topic):
    """Return [(publisher URI, connection)] of this node's subscription to topic (resolved)."""
    impl = get_topic_manager().get_subscriber_impl(topic)
    return [(c.endpoint_id, c) for c in (impl.connections if impl else [])]


class LinkRecovery:
    """Reconnect this node's subscriptions to a host whose stream got stuck (see the module).

    Args:
        name: the node's name, for log lines.
        topics: the watched topics (names as the node subscribes them, resolved here).
        probe(uri) -> bool: whether a node answers (default answers()).
        clock(): monotonic seconds.
    """

    def __init__(self, name, topics, probe=answers, clock=time.monotonic):
        self._name, self._probe, self._clock = name, probe, clock
        self._topics = [rospy.resolve_name(t) for t in topics]
        self._stuck = StuckConnections()
        self._probed = {}  # host -> monotonic time of its last probe
        self.reconnections = 0
        self._lock = threading.Lock()
        self.loop = Loop(Guard(name, rospy.logerr), 'link recovery', PROBE_PERIOD_S,
                         self.check)

    def start(self):
        self.loop.start()
        return self

    def check(self):
        """One round: find stuck watched connections, probe their hosts, reconnect those that
        answer."""
        now = self._clock()
        counts = {(topic, uri): (id(conn), conn.stat_bytes)
                  for topic in self._topics for uri, conn in connections(topic)}
        with self._lock:
            stuck = self._stuck.update(now, counts)
        by_host = {}
        for (topic, uri), silent_s in stuck.items():
            by_host.setdefault(host_of(uri), (topic, uri, silent_s))
        for host, (topic, uri, silent_s) in by_host.items():
            if now - self._probed.get(host, -1e9) < PROBE_PERIOD_S:
                continue
            self._probed[host] = now
            if self._probe(uri):
                rospy.logwarn('%s: nothing on %s for %.1f s, but its publisher answers: the link '
                              'to %s is back and its connections stuck; connecting anew',
                              self._name, topic, silent_s, host)
                self.reconnect(host)
                with self._lock:
                    self._stuck.reconnected([key for key in counts if host_of(key[1]) == host])

    def reconnect(self, host):
        """Close every subscriber connection of this node to a publisher on host and ask rospy
        (publisherUpdate on this node's own slave API) to connect to those publishers again."""
        manager = get_topic_manager()
        for topic, _ in manager.get_subscriptions():
            impl = manager.get_subscriber_impl(topic)
            if impl is None:
                continue
            uris = [c.endpoint_id for c in impl.connections]
            for conn in list(impl.connections):
                if host_of(conn.endpoint_id) == host:
                    impl.remove_connection(conn)
                    conn.close()
            if any(host_of(uri) == host for uri in uris):
                own = xmlrpc.client.ServerProxy(rospy.get_node_uri(),
                                                transport=_TimeoutTransport(2.0))
                own.publisherUpdate(rospy.get_name(), topic, uris)
        self.reconnections += 1
