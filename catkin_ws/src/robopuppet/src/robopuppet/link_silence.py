"""Which of a node's subscriber connections across the operator-robot link are stuck (pure).

link_recovery watches them with StuckConnections and reconnects the stuck ones.
"""
import urllib.parse

SILENT_S = 1.0          # a watched connection silent this long may be stuck
RETRY_SILENCES_S = (2.0, 4.0, 8.0)  # a reconnection that brought nothing: tried again after


class StuckConnections:
    """Which watched connections received nothing for silent_s after receiving something (pure).

    A connection is a key (topic, publisher URI) with a connection identity and a received
    byte count; a new identity (a new connection) starts unarmed: it is reported only after its
    first bytes and silent_s without more. But the connection that replaces one this node
    reconnected (reconnected()) is armed from its start, with the silences of RETRY_SILENCES_S
    one after the other: a reconnection made as the link came back may bring nothing, and is
    tried again; a publisher quiet of its own accord costs at most 1 + len(RETRY_SILENCES_S)
    reconnections. Data on a key ends its retries.
    """

    def __init__(self, silent_s=SILENT_S):
        self._silent_s = silent_s
        self._seen = {}     # key -> (identity, bytes, time of the last change, armed, silence)
        self._retries = {}  # key -> reconnections in a row that brought nothing yet

    def reconnected(self, keys):
        """This node reconnected these keys: arm their next connections (see the class)."""
        for key in keys:
            self._retries[key] = self._retries.get(key, -1) + 1

    def update(self, now_s, counts):
        """Take {key: (identity, bytes received)} of the watched connections now; return the
        keys silent for their bound, with how long: {key: seconds}."""
        seen, stuck = {}, {}
        for key, (identity, count) in counts.items():
            old = self._seen.get(key)
            if old is None or old[0] != identity:
                tries = self._retries.get(key)
                retry = tries is not None and tries < len(RETRY_SILENCES_S)
                seen[key] = (identity, count, now_s, count > 0 or retry,
                             RETRY_SILENCES_S[tries] if retry else self._silent_s)
            elif count != old[1]:
                seen[key] = (identity, count, now_s, True, self._silent_s)
                self._retries.pop(key, None)
            else:
                seen[key] = old
                if old[3] and now_s - old[2] >= old[4]:
                    stuck[key] = now_s - old[2]
        self._seen = seen
        return stuck


def host_of(uri):
    """Return the host name or address of a ROS node's XML-RPC URI."""
    return urllib.parse.urlparse(uri).hostname or ''
