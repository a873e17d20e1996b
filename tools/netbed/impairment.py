"""One direction of the bed's link: one-way delay, jitter, loss and cuts, as a pure scheduler.

No I/O and no clock: the forwarder hands each packet in with the time it arrived and asks which
packets are due at a given time. Every random draw comes from the direction's own seeded
generator, so a run with the same seed and the same packet sequence drops the same packets and
draws the same delays.

    link = Impairment(seed='1:to-robot')
    link.configure(delay_s=0.050, jitter_s=0.010, loss=0.01)
    link.offer(packet, now_s)          # queued, or counted as lost / cut / overflow
    for packet in link.due(now_s): ... # the packets whose release time has come, in order
    link.due_timed(now_s)              # the same as (packet, offered_s, release_s) tuples

Model (the choices a real path makes, unlike a naive scheduler):
- delay: each packet's one-way delay is delay_s + uniform(-jitter_s, +jitter_s), at least 0
  (netem's default jitter distribution).
- order: a packet is never released before the one offered before it (release time =
  max(sampled, previous release)), so TCP sees delay and loss, not massive reordering. With
  jitter at a high packet rate this raises the delay towards delay_s + jitter_s, as queueing does.
- loss: each packet is lost with probability `loss`, independently.
- cut: while cut, every packet offered is dropped, and so are the packets in flight when the
  cut begins (a pulled cable); restore lets packets through again.
- queue: at most max_queue packets in flight; more are dropped (overflow), as a full router
  queue would.
"""
import collections
import random

DEFAULT_MAX_QUEUE = 20000


class Impairment:
    """Delay, jitter, loss and cuts of one direction of the link (times in seconds)."""

    def __init__(self, seed, max_queue=DEFAULT_MAX_QUEUE):
        self._rng = random.Random(seed)
        self._queue = collections.deque()  # (release_s, packet, offered_s); release never decreases
        self._last_release_s = float('-inf')
        self.max_queue = max_queue
        self.delay_s = 0.0
        self.jitter_s = 0.0
        self.loss = 0.0
        self.is_cut = False
        self.counts = {'offered': 0, 'released': 0, 'lost': 0, 'cut': 0, 'overflow': 0}

    def configure(self, delay_s=None, jitter_s=None, loss=None):
        """Change some settings; those left None keep their value.

        Raises:
            ValueError: a negative delay or jitter, or a loss outside [0, 1].
        """
        for name, value in (('delay_s', delay_s), ('jitter_s', jitter_s)):
            if value is not None and not value >= 0.0:
                raise ValueError('%s must be >= 0, not %r' % (name, value))
        if loss is not None and not 0.0 <= loss <= 1.0:
            raise ValueError('loss must be within [0, 1], not %r' % (loss,))
        if delay_s is not None:
            self.delay_s = float(delay_s)
        if jitter_s is not None:
            self.jitter_s = float(jitter_s)
        if loss is not None:
            self.loss = float(loss)

    def cut(self):
        """Cut this direction: drop what is in flight and everything offered until restore."""
        self.is_cut = True
        self.counts['cut'] += len(self._queue)
        self._queue.clear()

    def restore(self):
        """Let packets through again after a cut."""
        self.is_cut = False

    def offer(self, packet, now_s):
        """Take a packet that arrived at now_s; return True when it was queued for release."""
        self.counts['offered'] += 1
        # Both draws happen for every packet, so the sequence of draws does not depend on the
        # settings or on cuts: a seed gives the same losses for the same traffic.
        lost = self._rng.random() < self.loss
        offset_s = self._rng.uniform(-self.jitter_s, self.jitter_s)
        if self.is_cut:
            self.counts['cut'] += 1
            return False
        if lost:
            self.counts['lost'] += 1
            return False
        if len(self._queue) >= self.max_queue:
            self.counts['overflow'] += 1
            return False
        release_s = max(now_s + max(self.delay_s + offset_s, 0.0), self._last_release_s)
        self._last_release_s = release_s
        self._queue.append((release_s, packet, now_s))
        return True

    def next_release_s(self):
        """Return the release time of the next packet in flight, or None when none is."""
        return self._queue[0][0] if self._queue else None

    def due(self, now_s):
        """Remove and return the packets whose release time is <= now_s, oldest first."""
        return [packet for packet, _, _ in self.due_timed(now_s)]

    def due_timed(self, now_s):
        """Remove and return (packet, offered_s, release_s) of the packets whose release time
        is <= now_s, oldest first: the times a trace of the link needs."""
        out = []
        queue = self._queue
        while queue and queue[0][0] <= now_s:
            release_s, packet, offered_s = queue.popleft()
            out.append((packet, offered_s, release_s))
        self.counts['released'] += len(out)
        return out

    def in_flight(self):
        """Return how many packets wait for their release time."""
        return len(self._queue)

    def status(self):
        """Return the settings and counters as a dict (times in ms), for the control socket."""
        return dict(self.counts, delay_ms=self.delay_s * 1e3, jitter_ms=self.jitter_s * 1e3,
                    loss=self.loss, is_cut=self.is_cut, in_flight=len(self._queue))
