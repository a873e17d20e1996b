#!/usr/bin/python3
"""Benchmark false frames from line noise, before and after robopuppet.protocol.state_set.

Usage (from the repository, after tools/setup.sh):
    . tools/env.sh && catkin_ws/src/robopuppet/benchmarks/bench_serial_noise.py \
        [--noise-bytes 1000000] [--seed 1]

Pure (no ROS): seeded noise, alone (a dead line) and in bursts between clean state sets (a live
line, 10 Hz sets and a 1 Hz heartbeat, as the firmware sends them), is fed to
- BEFORE: codec.Decoder alone and the serial node's old rule (every decoded frame published; a
  joint_states set whenever joint 6 arrives and all seven joints came since the last joint 6);
- AFTER: state_set.Receiver (plausibility, whole sets in order, healthy heartbeats).
A published frame, set or heartbeat is false when it is not the real one being sent. Clean-set
recovery is the share of the real sets that come out intact. Prints a table per noise kind;
passes or fails nothing.
"""
import argparse
import random
import sys

from robopuppet import interface, settings
from robopuppet.protocol import codec, state_set

LIMITS_V = (settings.DEFAULTS['voltage_min'], settings.DEFAULTS['voltage_max'])  # V, held
SET_PERIOD_S = 0.1
HEARTBEAT_EVERY = 10  # sets


def uniform(rng, size):
    return bytes(rng.randrange(256) for _ in range(size))


PALETTE = (0xA5,) * 4 + (0x00,) * 4 + (0x20, 0x40, 0x41, 0x01, 0x02, 0x03, 0x3F, 0x80)


def start_rich(rng, size):
    """Noise rich in start bytes, real ids and small numbers (a floating line, bit slips)."""
    return bytes(rng.choice(PALETTE) for _ in range(size))


def fragments(rng, size):
    """Cut-off real-looking frames (e.g. a USB packet lost, a replug) with random values."""
    out = bytearray()
    while len(out) < size:
        message = rng.choice((
            codec.JointState(rng.randrange(7), rng.randrange(3), rng.uniform(-3.1, 3.1),
                             rng.uniform(-7.0, 7.0)),
            codec.Gripper(rng.randrange(4), rng.random()), codec.Buttons(rng.randrange(5)),
            codec.Heartbeat()))
        frame = codec.encode(message)
        out += frame[:rng.randrange(1, len(frame) + 1)]
    return bytes(out[:size])


NOISE_KINDS = (('uniform random bytes', uniform), ('start-rich (A5/00/ids)', start_rich),
               ('cut-off frames', fragments))


def real_set(seq):
    """The seq-th real state set: values vary with seq, all plausible."""
    joints = [codec.JointState(j, 0, ((seq * 7 + j) % 384) / 64.0 - 3.0,
                               ((seq + j) % 112) / 8.0 - 7.0) for j in settings.JOINTS]
    grippers = [codec.Gripper(g, ((seq + g) % 64) / 64.0) for g in range(interface.NUM_GRIPPERS)]
    return joints + grippers + [codec.Buttons(seq % 5)]


class Before:
    """Today's behaviour: the decoder alone, and the old node's joint-set rule."""

    def __init__(self):
        self.decoder = codec.Decoder(codec.types_sent_by(codec.TO_HOST))
        self.seen, self.joint_real = set(), [False] * settings.NUM_JOINTS
        self.false_frames = self.false_heartbeats = self.false_sets = 0
        self.real_sets_out = 0

    def feed(self, data, real, _now_s):
        """real: the message these bytes end (None for noise)."""
        for message in self.decoder.feed(data):
            is_real = real is not None and message == real
            if not is_real:
                self.false_frames += 1
                self.false_heartbeats += type(message) is codec.Heartbeat
            if type(message) is codec.JointState:
                self.seen.add(message.joint)
                self.joint_real[message.joint] = is_real
                if message.joint == settings.NUM_JOINTS - 1:
                    if len(self.seen) == settings.NUM_JOINTS:
                        if all(self.joint_real):
                            self.real_sets_out += 1
                        else:
                            self.false_sets += 1
                    self.seen.clear()


class After:
    """The new receive layer."""

    def __init__(self):
        self.receiver = state_set.Receiver(lambda joint: LIMITS_V)
        self.false_frames = self.false_heartbeats = self.false_sets = 0
        self.real_sets_out = 0
        self.expected_set = None
        self.after_real_heartbeat = False

    def feed(self, data, real, now_s):
        # A heartbeat after dropped bytes comes out with the frame after it.
        real_heartbeat = real == codec.Heartbeat() or self.after_real_heartbeat
        self.after_real_heartbeat = real == codec.Heartbeat()
        for event in self.receiver.feed(data, now_s):
            if type(event) is codec.Heartbeat:
                if not real_heartbeat:
                    self.false_heartbeats += 1
                    self.false_frames += 1
            elif (real is not None and type(real) is codec.Buttons
                  and list(event.joints) == self.expected_set[:7]
                  and list(event.grippers) == [m.reading for m in self.expected_set[7:11]]
                  and event.button == self.expected_set[11].button):
                self.real_sets_out += 1
            else:
                self.false_sets += 1
                self.false_frames += len(state_set.SET_ORDER)


def run(noise, noise_bytes, live, rng):
    """Feed noise_bytes of noise (with real sets between bursts if live) to both sides."""
    sides = (Before(), After())
    sent_sets = sent_beats = 0
    now_s, left = 0.0, noise_bytes
    while left > 0:
        burst = noise(rng, min(left, rng.randrange(1, 200) if live else 4096))
        left -= len(burst)
        for side in sides:
            side.feed(burst, None, now_s)
        if not live:
            continue
        pieces = []
        if sent_sets % HEARTBEAT_EVERY == 0:
            pieces.append(codec.Heartbeat())
            sent_beats += 1
        messages = real_set(sent_sets)
        sides[1].expected_set = messages
        pieces.extend(messages)
        for message in pieces:
            frame = codec.encode(message)
            for side in sides:
                side.feed(frame, message, now_s)
        sent_sets += 1
        now_s += SET_PERIOD_S
    return sides, sent_sets, sent_beats


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--noise-bytes', type=int, default=1000000)
    parser.add_argument('--seed', type=int, default=1)
    args = parser.parse_args()
    per = 1e6 / args.noise_bytes
    print('%d noise bytes per row, seed %d; figures per 10^6 noise bytes' % (args.noise_bytes,
                                                                            args.seed))
    header = ('%-24s %-5s | %-33s | %-33s' % ('noise', 'line', 'BEFORE false frames/sets/beats',
                                               'AFTER false frames/sets/beats')
              + ' | clean sets recovered before / after')
    print(header)
    print('-' * len(header))
    for name, noise in NOISE_KINDS:
        for live in (False, True):
            rng = random.Random('%d %s %s' % (args.seed, name, live))
            (before, after), sets, beats = run(noise, args.noise_bytes, live, rng)
            row = '%-24s %-5s | %9.0f %9.1f %9.1f     | %9.1f %9.1f %9.1f    ' % (
                name, 'live' if live else 'dead', before.false_frames * per,
                before.false_sets * per, before.false_heartbeats * per, after.false_frames * per,
                after.false_sets * per, after.false_heartbeats * per)
            if live:
                row += ' | %6.2f %% / %6.2f %% of %d sets (%d heartbeats sent, %d counted)' % (
                    100.0 * before.real_sets_out / sets, 100.0 * after.real_sets_out / sets,
                    sets, beats, after.receiver.heartbeats)
            print(row)
    return 0


if __name__ == '__main__':
    sys.exit(main())
