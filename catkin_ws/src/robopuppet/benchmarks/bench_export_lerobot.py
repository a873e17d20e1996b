#!/usr/bin/python3
"""Benchmark: LeRobot dataset export time and size per minute of episode, against the HDF5's.

Builds bench_export.py's synthetic episode (the real system's rates, three cameras' 640x480
JPEG frames at 15 frames/s), then runs the export command in a child process for each output
and prints its wall and CPU time (with ffmpeg's) and size per minute of episode:

    python3 benchmarks/bench_export_lerobot.py [--minutes 1] [--fps 30] [--cameras 3]
        [--codecs h264,av1] [--keep DIR]

Outputs: `--format lerobot --fps F` per codec (images as recorded, 640x480), and
`--format aloha-hdf5 --rate F` at its default 320x240 and at full size (lzf).
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time

import bench_export

COMMAND = [sys.executable, '-c', 'from robopuppet.episodes import export_cli; export_cli.main()']


def folder_bytes(path):
    """Return the bytes of a file, or of every file under a folder."""
    if os.path.isfile(path):
        return os.path.getsize(path)
    return sum(os.path.getsize(os.path.join(folder, name))
               for folder, _, names in os.walk(path) for name in names)


def timed_export(argv):
    """Run the export command; return (exit code, wall s, CPU s of it and its children)."""
    started = time.perf_counter()
    child = subprocess.Popen(COMMAND + argv, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(child.pid, 0)
    return (os.waitstatus_to_exitcode(status), time.perf_counter() - started,
            usage.ru_utime + usage.ru_stime)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--minutes', type=float, default=1.0)
    parser.add_argument('--fps', type=int, default=30)
    parser.add_argument('--cameras', type=int, default=3, choices=range(4))
    parser.add_argument('--codecs', default='h264,av1')
    parser.add_argument('--keep', metavar='DIR')
    args = parser.parse_args()
    directory = args.keep or tempfile.mkdtemp(prefix='bench_export_lerobot_')
    try:
        frames = bench_export.camera_frames(bench_export.DEFAULT_FRAMES, args.cameras)
        bag_path, count = bench_export.write_episode(directory, args.minutes, frames)
        print('episode: %.1f min, %d messages, %.1f MB bag, %d cameras at 640x480; load '
              'average %.1f' % (args.minutes, count, os.path.getsize(bag_path) / 1e6,
                                args.cameras, os.getloadavg()[0]), flush=True)
        runs = []
        for codec in args.codecs.split(','):
            out = os.path.join(directory, 'lerobot_' + codec)
            shutil.rmtree(out, ignore_errors=True)
            runs.append(('lerobot %s 640x480 %d fps' % (codec, args.fps), out,
                         [bag_path, '--format', 'lerobot', '--out', out, '--fps',
                          str(args.fps), '--video-codec', codec]))
        for size in ('320x240', 'full'):
            out = os.path.join(directory, 'hdf5_' + size)
            os.makedirs(out, exist_ok=True)
            runs.append(('aloha-hdf5 %s lzf %d Hz' % (size, args.fps),
                         os.path.join(out, bench_export.NAME + '.hdf5'),
                         [bag_path, '--format', 'aloha-hdf5', '--rate', str(args.fps),
                          '--image-size', size, '--out', out, '--yes']))
        print('%-30s %6s %9s %9s %10s %10s %10s' % ('output', 'exit', 'wall s', 'CPU s',
                                                   'CPU s/min', 'MB', 'MB/min'))
        for label, out, argv in runs:
            code, wall_s, cpu_s = timed_export(argv)
            size_mb = folder_bytes(out) / 1e6 if os.path.exists(out) else 0.0
            print('%-30s %6d %9.1f %9.1f %10.1f %10.1f %10.1f' % (
                label, code, wall_s, cpu_s, cpu_s / args.minutes, size_mb,
                size_mb / args.minutes), flush=True)
    finally:
        if not args.keep:
            shutil.rmtree(directory, ignore_errors=True)


if __name__ == '__main__':
    main()
