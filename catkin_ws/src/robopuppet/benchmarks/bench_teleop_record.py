"""bench_teleop.py --record: puppet movement to JointCommand latency with recording on vs off.

Not run by itself: bench_teleop.py starts the roscore, the Baxter stand-in and side R's host
stack at comm_rate 100, then calls run(). Modes (MODES): no recorder; the real recorder running
idle, started as recorder.launch starts it (record_sides:=R, record_sim:=true), subscribed to
user_btn only; and recording, an episode of the whole traffic started and stopped through
/puppet/record (the recorder subscribes to the other topics at its start). The samples of a
mode are spread over rounds of interleaved blocks (order reversed every other round), so that a
change of the machine's load from other processes falls on every mode alike.
"""
import math
import os
import statistics
import sys
import time

import rosbag
import rospy

from bench_support import percentile, start_process, stop_process
from robopuppet import interface
from robopuppet_msgs.srv import Record

OFF, IDLE, ON = 'no recorder', 'recorder idle', 'recording'
MODES = (OFF, IDLE, ON)
TARGET_ADDED_MS = 1.0      # target: recording adds at most this much to the p99
SETTLE_S = 3.0             # after the recorder's service is up: connections made, start-up over
WATCHED = ('config', 'serial', 'arm', 'baxter_sim', 'recorder')


class RecorderLaunch:
    """recorder.launch for side R, episodes under work; stopped by its process group."""

    def __init__(self, work, log):
        self.process = start_process(
            ['roslaunch', 'robopuppet', 'recorder.launch', 'record_sides:=R', 'record_sim:=true',
             'episodes_dir:=' + os.path.join(work, 'episodes')], log)
        try:
            self._record = rospy.ServiceProxy(interface.RECORD_SERVICE, Record)
            self._record.wait_for_service(30)
            time.sleep(SETTLE_S)
        except BaseException:
            self.close()
            raise

    def record(self, start):
        """Start (True) or stop an episode through /puppet/record; return its bag file."""
        answer = self._record(start, 'bench_teleop --record' if start else '', '')
        if not answer.ok:
            raise RuntimeError('/puppet/record refused: %s' % answer.error)
        return answer.episode

    def close(self):
        stop_process(self.process)


def run(stack, samples, rounds, work, log, baxter):
    """Measure every mode on the running stack in interleaved blocks; print the figures."""
    per_block = max(1, int(math.ceil(samples / float(rounds))))
    blocks = {mode: [] for mode in MODES}
    episodes = []
    recorder = None
    try:
        for round_index in range(rounds):
            for mode in MODES if round_index % 2 == 0 else MODES[::-1]:
                if mode == OFF and recorder is not None:
                    recorder.close()
                    recorder = None
                elif mode != OFF and recorder is None:
                    recorder = RecorderLaunch(work, log)
                others = {'baxter_sim': baxter}
                if recorder is not None:
                    others['recorder'] = recorder.process
                if mode == ON:
                    episodes.append(recorder.record(True))
                    time.sleep(1.0)  # the episode's subscriptions connect within ~0.3 s
                block = stack.measure(per_block, others)
                if mode == ON:
                    recorder.record(False)
                if not block.latencies:
                    raise RuntimeError('%s: no move arrived in a block' % mode)
                blocks[mode].append(block)
                print('round %d/%d %-13s p50 %5.1f ms  p99 %5.1f ms  machine busy %3.0f %%  '
                      'faults %d' % (round_index + 1, rounds, mode,
                                     1000 * statistics.median(block.latencies),
                                     1000 * percentile(block.latencies, 0.99), block.busy,
                                     block.faults), file=sys.stderr, flush=True)
    finally:
        if recorder is not None:
            recorder.close()
    report(blocks, per_block * rounds, rounds, episodes)


def report(blocks, count, rounds, episodes):
    """Print p50/p99 per mode, what recording adds, CPU use and wait, what the episodes hold."""
    print('Latency from a puppet movement to the first JointCommand carrying it, comm_rate 100,')
    print('recording on vs off (%d rounds of interleaved blocks of %d moves per mode)' % (
        rounds, count // rounds))
    print('%-14s %7s %7s %7s %7s %6s %15s' % ('mode', 'samples', 'p50 ms', 'p99 ms', 'max ms',
                                             'cmd/s', 'machine busy %'))
    figures = {}
    for mode in MODES:
        latencies = [t for block in blocks[mode] for t in block.latencies]
        figures[mode] = (1000 * statistics.median(latencies), 1000 * percentile(latencies, 0.99))
        lost = count - len(latencies)
        faults = sum(b.faults for b in blocks[mode])
        print('%-14s %7d %7.1f %7.1f %7.1f %6.0f %15.0f%s%s' % (
            mode, len(latencies), figures[mode][0], figures[mode][1], 1000 * max(latencies),
            statistics.mean(b.command_rate for b in blocks[mode]),
            statistics.mean(b.busy for b in blocks[mode]),
            '  (%d moves never arrived)' % lost if lost else '',
            ', %d arm_R faults' % faults if faults else ''))
    for base in (OFF, IDLE):
        paired = [1000 * (percentile(on.latencies, 0.99) - percentile(off.latencies, 0.99))
                  for on, off in zip(blocks[ON], blocks[base])]
        print('recording adds vs %s: p50 %+.2f ms, p99 %+.2f ms; median of the rounds\' p99 '
              'differences %+.2f ms, %d of %d rounds worse (target: p99 <= %.0f ms added)' % (
                  base, figures[ON][0] - figures[base][0], figures[ON][1] - figures[base][1],
                  statistics.median(paired), sum(d > 0 for d in paired), len(paired),
                  TARGET_ADDED_MS))
    print('p99 ms per round: ' + '; '.join('%s %s' % (mode, ' '.join(
        '%.1f' % (1000 * percentile(b.latencies, 0.99)) for b in blocks[mode]))
                                           for mode in MODES))
    print('per process (%s): CPU %% of one core | waiting for a CPU, ms per s' % (
        ' '.join(WATCHED)))
    for mode in MODES:
        print('%-14s %s | %s' % (mode, per_process(blocks[mode], 'cpu'),
                                 per_process(blocks[mode], 'wait')))
    print(episode_summary(episodes), flush=True)


def per_process(blocks, field):
    """Return the blocks' mean of a per-process figure (Block.cpu or .wait), '-' when absent."""
    return ' '.join('%5.1f' % statistics.mean(getattr(b, field)[key] for b in blocks)
                    if key in blocks[0].cpu else '    -' for key in WATCHED)


def episode_summary(episodes):
    """Return a line on what the recorded episodes hold (messages, topics, MB, minutes)."""
    messages, topics, size_mb, minutes = 0, set(), 0.0, 0.0
    for path in episodes:
        with rosbag.Bag(path) as bag:
            info = bag.get_type_and_topic_info().topics
            minutes += (bag.get_end_time() - bag.get_start_time()) / 60.0
        messages += sum(t.message_count for t in info.values())
        topics.update(info)
        size_mb += os.path.getsize(path) / 1e6
    return 'episodes: %d, %.1f min, %d messages on %d topics, %.1f MB (%.1f MB per minute)' % (
        len(episodes), minutes, messages, len(topics), size_mb, size_mb / max(minutes, 1e-9))
