"""Keep a serial port open: a reader thread that reconnects by itself, and locked writes.

The transport only; it knows nothing of frames or ROS. It reports through callbacks, which it
calls from its reader thread, and through two logging callables so that a node can route the
messages to its log. Each problem (port missing, port lost) is logged once until it is solved.
Any exception from opening, reading or closing the port (pyserial lets termios.error and others
through, not only SerialException and OSError) counts as a missing or lost port: the reader
thread never dies of it.
"""
import threading

import serial

READ_TIMEOUT_S = 0.2
WRITE_TIMEOUT_S = 0.5


class SerialLink:
    """One serial port, opened and re-opened by a reader thread.

    Args:
        port: device path, e.g. /dev/ttyACM0 or a pseudo-terminal link.
        baud_rate: bits per second.
        on_connect(): called after each successful open, before any data is delivered.
        on_data(data): called with each chunk of received bytes.
        log_info(text), log_warn(text): where state changes are reported.
        retry_s: pause between attempts to open a missing or failed port.
        serial_factory: the class used to open the port (serial.Serial; tests may replace it).
    """

    def __init__(self, port, baud_rate, on_connect, on_data, log_info, log_warn,
                 retry_s=1.0, serial_factory=serial.Serial):
        self.port = port
        self._baud_rate = baud_rate
        self._on_connect = on_connect
        self._on_data = on_data
        self._log_info = log_info
        self._log_warn = log_warn
        self._retry_s = retry_s
        self._factory = serial_factory
        self._serial = None
        self._write_lock = threading.Lock()
        self._stop = threading.Event()
        self._reopen = threading.Event()
        self._thread = threading.Thread(target=self._run, name='serial-reader', daemon=True)
        self.connects = 0
        self.write_errors = 0
        self.callback_errors = 0
        self.close_errors = 0

    @property
    def connected(self):
        """Return True while the port is open."""
        return self._serial is not None

    def start(self):
        """Start the reader thread."""
        self._thread.start()

    def stop(self, timeout_s=2.0):
        """Stop the reader thread and close the port."""
        self._stop.set()
        port = self._serial
        if port is not None:
            port.cancel_read()
        self._thread.join(timeout_s)

    def reopen(self):
        """Ask the reader thread to close the port and open it again (e.g. a silent device)."""
        self._reopen.set()
        port = self._serial
        if port is not None:
            port.cancel_read()

    def write(self, data):
        """Write bytes to the port as one write; return True only if the port took all of them.

        A failure or a short write (the driver took less) counts as a write error. Callers that
        must keep frames whole on the device side write whole frames per call.
        """
        with self._write_lock:
            port = self._serial
            if port is None:
                return False
            try:
                written = port.write(data)
                if written is None or written == len(data):
                    return True
                error = 'the port took %d of %d bytes' % (written, len(data))
            except (serial.SerialException, OSError) as exception:
                error = exception
            self.write_errors += 1
            if self.write_errors == 1 or self.write_errors % 100 == 0:
                self._log_warn('write to %s failed (%d so far): %s'
                               % (self.port, self.write_errors, error))
            return False

    def _run(self):
        # The problem logged last: a port that stays missing, or is lost and then missing while
        # it comes back, is logged once.
        problem = None
        reopening = False  # a re-open asked for by reopen() is not news: no log line
        while not self._stop.is_set():
            port, error = self._open()
            if port is None:
                kind = (type(error).__name__, getattr(error, 'errno', None))
                if problem not in ('lost', kind):
                    self._log_warn('cannot open serial port %s: %s; retrying every %.1f s'
                                   % (self.port, _describe(error), self._retry_s))
                    problem = kind
                self._stop.wait(self._retry_s)
                continue
            self._reopen.clear()
            with self._write_lock:
                self._serial = port
            self.connects += 1
            if not reopening:
                self._log_info('serial port %s open at %d baud' % (self.port, self._baud_rate))
            problem = None
            self._call(self._on_connect)
            lost = self._read_until_lost(port)
            with self._write_lock:
                self._serial = None
                self._close(port)
            reopening = not lost
            if lost:
                self._log_warn('serial port %s lost: %s; retrying every %.1f s'
                               % (self.port, lost, self._retry_s))
                problem = 'lost'
                self._stop.wait(self._retry_s)

    def _open(self):
        """Return (open port with an empty input buffer, None) or (None, the error)."""
        port = None
        try:
            port = self._factory(self.port, self._baud_rate, timeout=READ_TIMEOUT_S,
                                 write_timeout=WRITE_TIMEOUT_S)
            port.reset_input_buffer()
            return port, None
        # pyserial lets termios.error (not an OSError) and others through from open(): whatever
        # it is, the reader thread must live on and retry.
        except Exception as error:  # pylint: disable=broad-except
            if port is not None:
                self._close(port)
            return None, error

    def _read_until_lost(self, port):
        """Deliver data until stop or reopen (return None) or an error (return its text)."""
        while not self._stop.is_set():
            if self._reopen.is_set():
                return None
            try:
                data = port.read(max(1, port.in_waiting))
            except Exception as error:  # pylint: disable=broad-except
                return _describe(error)
            if data:
                self._call(self._on_data, data)
        return None

    def _close(self, port):
        """Close a port that failed, was lost or is re-opened; a failure is logged once."""
        try:
            port.close()
        except Exception as error:  # pylint: disable=broad-except
            self.close_errors += 1
            if self.close_errors == 1:
                self._log_warn('closing serial port %s failed: %s; port dropped'
                               % (self.port, _describe(error)))

    def _call(self, callback, *args):
        # A faulty handler must not stop the link: log it and keep reading.
        try:
            callback(*args)
        except Exception as error:  # pylint: disable=broad-except
            self.callback_errors += 1
            self._log_warn('serial handler %s failed: %r' % (callback.__name__, error))



def _describe(error):
    """Return an exception as text that names its type when that is not obvious."""
    if isinstance(error, (serial.SerialException, OSError)):
        return str(error)
    return '%s: %s' % (type(error).__name__, error)
