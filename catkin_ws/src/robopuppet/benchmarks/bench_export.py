#!/usr/bin/python3
"""Benchmark: export time per minute of episode.

Builds a synthetic 1-minute episode at the real system's rates (Baxter's joint and gripper
states at 100 Hz, the right arm's commands at 50 Hz, puppet R's joint states and four grippers
at 10 Hz, diagnostics at 1 Hz, three cameras' 640x480 JPEG frames (quality 80) at 15 frames/s),
then times each stage of the export and prints the figures, with the HDF5's MB per minute.

    python3 benchmarks/bench_export.py [--minutes 1] [--repeat 3] [--keep DIR] [--rate HZ]
        [--cameras 3] [--frames IMAGE] [--compression lzf|gzip|none]
        [--image-size WxH|full] [--memory]

The frames are 640x480 windows of IMAGE (default docs/images/sim_cameras.jpg: the simulated
room and hand cameras), shifted a few pixels from frame to frame; give a photograph to see what
a webcam's frames cost. --compression overrides the images' HDF5 filter (gzip: h5py's default
level, 4). --image-size scales the images as export does (default its 320x240; full: as
recorded, 640x480).
--keep DIR leaves the episode and its outputs (.hdf5, .csv, .png) in DIR to look at.
--memory runs the whole export command instead (`export EPISODE --format all --rate HZ`) in a
child process, --repeat times, and prints its peak resident memory, wall and CPU time, e.g.
`--memory --minutes 30 --cameras 0` (a 30-minute episode without images).
"""
import argparse
import math
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

import cv2
import genpy
import numpy as np
import rosbag
import yaml
from baxter_core_msgs.msg import EndEffectorCommand, EndEffectorState, JointCommand
from diagnostic_msgs.msg import DiagnosticArray
from robopuppet_msgs.msg import TeleopState
from sensor_msgs.msg import CompressedImage, JointState
from std_msgs.msg import Float32

from robopuppet.baxter_description import arm_joint_names
from robopuppet.cameras import jpeg
from robopuppet.episodes import (export, export_files, export_images, export_plot, export_size,
                                 export_writers)
from robopuppet.interface import BAXTER_CAMERAS, ROOM_CAMERA

T0_NS = 1700000000 * 10**9
NAME = 'episode_20240101-120000'
CAMERAS = (ROOM_CAMERA,) + BAXTER_CAMERAS[1:] + BAXTER_CAMERAS[:1]  # the sim's three, then head
FRAME_RATE_HZ, WIDTH, HEIGHT, QUALITY = 15, 640, 480, 80
DEFAULT_FRAMES = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', '..', '..',
                              'docs', 'images', 'sim_cameras.jpg')
COMPRESSION = {'lzf': 'lzf', 'gzip': 'gzip', 'none': None}  # --compression: h5py's filter


def camera_frames(path, cameras):
    """Return per camera FRAME_RATE_HZ JPEGs: 640x480 windows of the image at path (scaled up
    if smaller), one window per camera, shifted 2 px further each frame."""
    image = cv2.imread(path)
    if image is None:
        raise SystemExit('cannot read %s' % path)
    scale = max(WIDTH / image.shape[1], HEIGHT / image.shape[0], 1.0)
    if scale > 1.0:
        image = cv2.resize(image, (int(np.ceil(image.shape[1] * scale)),
                                   int(np.ceil(image.shape[0] * scale))))
    frames = []
    for c in range(cameras):
        x = (image.shape[1] - WIDTH) * c // max(cameras - 1, 1)
        window = image[:HEIGHT, x:x + WIDTH]
        frames.append([jpeg.encode(np.roll(window, 2 * k, axis=1), QUALITY)
                       for k in range(FRAME_RATE_HZ)])
    return frames


def puppet_angles(t):
    """Return puppet R's 7 angles (rad) at t s: slow sines of different periods."""
    return [0.6 * math.sin(2 * math.pi * t / (7.0 + 2 * j) + j) for j in range(7)]


def write_episode(directory, minutes, frames):
    """Write NAME.bag and NAME.yaml into directory, frames[c] cycling on camera c at
    FRAME_RATE_HZ; return the bag path and message count."""
    duration_s = 60.0 * minutes
    bag_path = os.path.join(directory, NAME + '.bag')
    left, right = arm_joint_names('left'), arm_joint_names('right')
    command = puppet_angles(0.0)
    measured = list(command)
    closed = False
    count = 0
    with rosbag.Bag(bag_path, 'w') as bag:
        bag.write('/puppet/arm_R/teleop_state', TeleopState(state='following', follow_right=True),
                  genpy.Time(0, T0_NS))
        for tick in range(int(duration_s * 100) + 1):  # 100 Hz
            t_s = tick / 100.0
            stamp = genpy.Time(0, T0_NS + tick * 10**7)
            pressed = 15.0 <= t_s % 40.0 < 30.0
            if tick % 10 == 0:  # the puppet's state set, 10 Hz
                puppet = puppet_angles(t_s)
                bag.write('/puppet/arm_R/joint_states', JointState(
                    name=['joint_%d' % j for j in range(7)], position=puppet), stamp)
                for g in range(4):
                    bag.write('/puppet/arm_R/gripper_%d' % g,
                              Float32(data=0.0 if pressed and g == 3 else 1.0), stamp)
                count += 5
            if tick % 2 == 0:  # arm_R's commands, 50 Hz
                command = puppet
                bag.write('/robot/limb/right/joint_command', JointCommand(
                    mode=JointCommand.POSITION_MODE, names=right, command=command), stamp)
                count += 1
            if pressed != closed:
                closed = pressed
                bag.write('/robot/end_effector/right_gripper/command', EndEffectorCommand(
                    command='go', args='{"position": %.1f}' % (0.0 if closed else 100.0)),
                    stamp)
                count += 1
            measured = [m + 0.08 * (c - m) for m, c in zip(measured, command)]  # lagging arm
            bag.write('/robot/joint_states', JointState(
                name=left + right, position=[0.0] * 7 + measured, velocity=[0.0] * 14,
                effort=[0.0] * 14), stamp)
            bag.write('/robot/end_effector/right_gripper/state', EndEffectorState(
                position=max(30.0, 100.0 - 80.0 * (t_s % 40.0 - 15.0)) if pressed else 100.0,
                force=30.0 if pressed else 0.0), stamp)
            count += 2
            if tick % 100 == 0:
                bag.write('/diagnostics', DiagnosticArray(), stamp)
                count += 1
            for k in range(tick * FRAME_RATE_HZ // 100, (tick + 1) * FRAME_RATE_HZ // 100):
                for c, jpegs in enumerate(frames):  # 15 frames/s, the first at 0.06 s
                    bag.write(export_images.frame_topic(CAMERAS[c]), CompressedImage(
                        format=jpeg.JPEG_FORMAT, data=jpegs[k % len(jpegs)]), stamp)
                    count += 1
    with open(os.path.join(directory, NAME + '.yaml'), 'w') as stream:
        yaml.safe_dump({'format_version': 1, 'name': NAME, 'sim': True, 'sides': ['R'],
                        'duration_s': duration_s, 'cameras': list(CAMERAS[:len(frames)])},
                       stream)
    return bag_path, count


def first_joint_state(bag_path):
    """Return the time (genpy.Time) of the bag's first /robot/joint_states."""
    bag = export_files.open_bag(bag_path)
    with bag:
        return export_files.index_times(bag, ['/robot/joint_states'])[0]


def timed(function, *args):
    started = time.perf_counter()
    result = function(*args)
    return result, time.perf_counter() - started


def export_command(bag_path, rate_hz, repeat, image_size):
    """Run the export command on the bag in a child process repeat times; print each run's peak
    resident memory (MB), wall and CPU time (s) and the files written."""
    argv = [sys.executable, '-c', 'from robopuppet.episodes import export_cli; '
            'export_cli.main()', bag_path, '--format', 'all', '--rate', str(rate_hz),
            '--image-size', image_size, '--yes']
    for _ in range(repeat):
        started = time.perf_counter()
        child = subprocess.Popen(argv, stdout=subprocess.DEVNULL)
        _, status, usage = os.wait4(child.pid, 0)
        wall_s = time.perf_counter() - started
        base = bag_path[:-len('.bag')]
        sizes = ', '.join('%s %.1f MB' % (suffix, os.path.getsize(base + suffix) / 1e6)
                          for suffix in ('.hdf5', '.csv') if os.path.exists(base + suffix))
        print('export command: exit %d, peak resident memory %.0f MB, %.1f s wall, %.1f s CPU; '
              '%s' % (os.waitstatus_to_exitcode(status), usage.ru_maxrss / 1e3, wall_s,
                      usage.ru_utime + usage.ru_stime, sizes), flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--minutes', type=float, default=1.0)
    parser.add_argument('--repeat', type=int, default=3)
    parser.add_argument('--keep', metavar='DIR')
    parser.add_argument('--rate', type=float, default=export.DEFAULT_RATE_HZ, metavar='HZ')
    parser.add_argument('--cameras', type=int, default=3, choices=range(len(CAMERAS) + 1))
    parser.add_argument('--frames', default=DEFAULT_FRAMES, metavar='IMAGE')
    parser.add_argument('--compression', choices=sorted(COMPRESSION))
    parser.add_argument('--image-size', default='%dx%d' % export_size.DEFAULT_IMAGE_SIZE,
                        metavar='WxH|full')
    parser.add_argument('--memory', action='store_true',
                        help='time the whole export command and print its peak memory')
    args = parser.parse_args()
    directory = args.keep or tempfile.mkdtemp(prefix='bench_export_')
    os.makedirs(directory, exist_ok=True)
    compression = (COMPRESSION[args.compression] if args.compression
                   else export_writers.IMAGE_COMPRESSION)
    size = export_size.parse_size(args.image_size)
    try:
        frames = camera_frames(args.frames, args.cameras)
        (bag_path, count), write_s = timed(write_episode, directory, args.minutes, frames)
        print('episode: %.1f min, %d messages, %.1f MB bag (written in %.1f s); %d cameras at '
              '%d frames/s, JPEG %.0f kB a frame' % (
                  args.minutes, count, os.path.getsize(bag_path) / 1e6, write_s, args.cameras,
                  FRAME_RATE_HZ, np.mean([len(j) for f in frames for j in f] or [0]) / 1e3),
              flush=True)
        if args.memory:
            export_command(bag_path, args.rate, args.repeat, args.image_size)
            return
        stages = {}
        base = os.path.join(directory, NAME)
        for _ in range(args.repeat):
            messages, t_read = timed(export_files.read_messages, bag_path,
                                     export.episode_topics())
            recording, t_collect = timed(export.collect, messages)
            arrays, t_arrays = timed(export.aloha_arrays, recording, args.rate)
            _, t_hdf5 = timed(export_writers.write_hdf5, base + '.hdf5', arrays, True,
                              args.rate, NAME)
            start = first_joint_state(bag_path)
            _, t_frames = timed(lambda: sum(1 for _ in export_files.read_frames(bag_path,
                                                                                start)))
            cpu_s = time.process_time()
            _, t_images = timed(lambda: export_writers.write_hdf5(
                base + '.hdf5', arrays, True, args.rate, NAME,
                export_files.read_frames(bag_path, start), compression=compression, size=size))
            cpu_s = time.process_time() - cpu_s
            _, t_csv = timed(lambda: open(base + '.csv', 'w').write(
                ''.join(line + '\n' for line in export.csv_lines(arrays))))
            series, t_series = timed(export_plot.plot_series, recording, arrays)
            _, t_plot = timed(export_plot.write_plot, base + '.png', series, arrays['time'],
                              NAME + ' (sim, benchmark)')
            for name, value in (('read bag', t_read), ('collect', t_collect),
                                ('resample (%g Hz)' % args.rate, t_arrays),
                                ('write hdf5', t_hdf5), ('(read frames)', t_frames),
                                ('hdf5 + images', t_images), ('  (its CPU time)', cpu_s),
                                ('csv rows + write', t_csv), ('plot series', t_series),
                                ('plot png', t_plot)):
                stages.setdefault(name, []).append(value)
        total = 0.0
        print('stage               best of %d (s per %.1f min)   s per minute of episode' % (
            args.repeat, args.minutes))
        for name, values in stages.items():
            if name not in ('write hdf5', '(read frames)', '  (its CPU time)'):  # within it
                total += min(values)
            print('  %-18s %8.3f %28.3f' % (name, min(values), min(values) / args.minutes))
        print('  %-18s %8.3f %28.3f' % ('total', total, total / args.minutes))
        hdf5_mb = os.path.getsize(base + '.hdf5') / 1e6
        print('T = %d steps; hdf5 with images (%s, %s) %.1f MB (%.1f MB per minute), csv %.2f MB, '
              'png %.2f MB' % (len(arrays['time']), args.compression or
                               export_writers.IMAGE_COMPRESSION, args.image_size, hdf5_mb,
                               hdf5_mb / args.minutes,
                               os.path.getsize(base + '.csv') / 1e6,
                               os.path.getsize(base + '.png') / 1e6))
        print('peak resident memory of this process %.0f MB (decoded, the frames of one '
              'minute would be %.0f MB)' % (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
                                            / 1e3, len(frames) * 60 * FRAME_RATE_HZ
                                            * WIDTH * HEIGHT * 3 / 1e6))
    finally:
        if not args.keep:
            shutil.rmtree(directory, ignore_errors=True)


if __name__ == '__main__':
    main()
