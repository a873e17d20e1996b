#!/usr/bin/python3
"""Benchmark the simulated cameras: frames/s rendered and delivered per camera, and their CPU.

Usage (after `. tools/env.sh`): bench_cameras.py [WINDOW_S [NICE]]  (defaults 15 s, the node's
~nice 10: with 0 the node competes for a busy CPU like the others)
First renders in this process without ROS (the renderer's ceiling: sim_cameras.SimCameras with
the joints moving every frame, one camera and three in turn). Then starts its own roscore on
a free port, the baxter_sim and sim_cameras nodes (rate 15 Hz, 640x480), enables the robot
and swings both arms (position mode, 100 Hz) so that every frame differs, and for each case
subscribes for WINDOW_S: nobody watching; the right hand camera's image/compressed; the three
default cameras' image/compressed; the three cameras' raw image. It prints per camera the
frames/s delivered (messages received here) and rendered (the node's /diagnostics), and the
sim_cameras process's CPU (% of one core, and ms of CPU per frame: what a loaded machine
cannot hide). Target: >= 15 frames/s per camera.
"""
import math
import os
import sys
import threading
import time

import psutil

from bench_support import private_roscore, start_process, stop_process
from robopuppet import baxter_description as bd, interface
from robopuppet.cameras import scene, sim_cameras

PKG = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CAMERAS = sim_cameras.DEFAULTS['cameras']
RATE_HZ = 15.0


def swinging(t_s):
    """Return joint positions of both arms swinging slowly about neutral at time t_s."""
    phase = 0.5 * math.sin(t_s)
    positions = {}
    for side in interface.BAXTER_SIDES:
        positions.update({n: bd.NEUTRAL_POSE[n.split('_')[1]] + phase
                          for n in bd.arm_joint_names(side)})
    return positions


def renderer_ceiling(names, frames=60):
    """Return (frames/s per camera, CPU % of one core) rendering names in turn, no ROS."""
    with open(bd.URDF_PATH) as urdf:
        text = urdf.read()
    world = scene.load_world(os.path.join(PKG, 'config', 'world.yaml'))
    core = sim_cameras.SimCameras(text, world, 640, 480, names)
    core.set_positions(swinging(0.0))
    for name in names:
        core.render(name)  # the OpenGL context and first frames: not timed
    wall, cpu = time.monotonic(), time.process_time()
    for frame in range(frames):
        core.set_positions(swinging(0.05 * (frame + 1)))
        for name in names:
            core.render(name)
    wall, cpu = time.monotonic() - wall, time.process_time() - cpu
    core.close()
    return frames / wall, 100.0 * cpu / wall


def command_loop(rospy, stop):
    """Send both arms the swinging positions in position mode at 100 Hz until stop is set."""
    from baxter_core_msgs.msg import JointCommand
    pubs = {side: rospy.Publisher(interface.limb_topic(side, 'joint_command'), JointCommand,
                                  queue_size=10) for side in interface.BAXTER_SIDES}
    rate = rospy.Rate(100)
    while not stop.is_set() and not rospy.is_shutdown():
        positions = swinging(time.monotonic())
        for side, pub in pubs.items():
            names = bd.arm_joint_names(side)
            pub.publish(JointCommand(mode=JointCommand.POSITION_MODE, names=names,
                                     command=[positions[n] for n in names]))
        rate.sleep()


def measure(rospy, node, topics, window_s, diagnostics):
    """Subscribe to topics [(camera, name, type)] for window_s; return ({camera: delivered
    frames/s}, {camera: rendered frames/s, the mean of the node's diagnostics in the window},
    node CPU %). diagnostics: the list the /diagnostics callback appends values lists to."""
    counts = {camera: 0 for camera, _, _ in topics}
    lock = threading.Lock()

    def on_frame(_msg, camera):
        with lock:
            counts[camera] += 1

    subs = [rospy.Subscriber(interface.camera_topic(camera, name), kind, on_frame, camera,
                             queue_size=5, buff_size=2 ** 24) for camera, name, kind in topics]
    time.sleep(3.0)  # connect and reach a steady rate
    with lock:
        counts = dict.fromkeys(counts, 0)
    process = psutil.Process(node.pid)
    del diagnostics[:]
    cpu, wall = sum(process.cpu_times()[:2]), time.monotonic()
    time.sleep(window_s)
    cpu, wall = sum(process.cpu_times()[:2]) - cpu, time.monotonic() - wall
    with lock:
        delivered = {camera: count / wall for camera, count in counts.items()}
    for sub in subs:
        sub.unregister()
    rendered = {}
    for values in diagnostics[1:]:  # the first one counts frames from before the window
        for value in values:
            camera, _, key = value.key.partition(' ')
            if key == 'rendered_hz':
                rendered.setdefault(camera, []).append(float(value.value))
    return delivered, {c: sum(r) / len(r) for c, r in rendered.items()}, 100.0 * cpu / wall


def main():
    window_s = float(sys.argv[1]) if len(sys.argv) > 1 else 15.0
    nice = int(sys.argv[2]) if len(sys.argv) > 2 else sim_cameras.DEFAULTS['nice']
    print('sim_cameras benchmark: 640x480, %d cores, load average %.1f'
          % (psutil.cpu_count(), os.getloadavg()[0]))
    print('renderer alone (no ROS, joints moving every frame):')
    for names in ([CAMERAS[-1]], CAMERAS):
        rate_hz, cpu = renderer_ceiling(names)
        print('  %d camera(s): %.1f frames/s each, CPU %.0f %% of one core, %.1f ms CPU a frame'
              % (len(names), rate_hz, cpu, 10.0 * cpu / (rate_hz * len(names))))
    with private_roscore('bench_cameras_') as work:
        log = open(os.path.join(work, 'nodes.log'), 'w')
        sim = start_process([os.path.join(PKG, 'nodes', 'baxter_sim')], log)
        cams = start_process([os.path.join(PKG, 'nodes', 'sim_cameras'),
                              '_rate:=%g' % RATE_HZ, '_nice:=%d' % nice], log)
        try:
            import rospy
            from diagnostic_msgs.msg import DiagnosticArray
            from sensor_msgs.msg import CompressedImage, Image, JointState
            from std_msgs.msg import Bool
            rospy.init_node('bench_cameras', disable_signals=True)
            rospy.wait_for_message(interface.ROBOT_JOINT_STATES, JointState, timeout=20.0)
            enable = rospy.Publisher(interface.SET_SUPER_ENABLE, Bool, queue_size=1, latch=True)
            enable.publish(Bool(True))
            newest = []

            def on_diagnostics(msg):
                newest.extend(s.values for s in msg.status
                              if s.name.endswith('simulated cameras'))

            rospy.Subscriber(interface.DIAGNOSTICS, DiagnosticArray, on_diagnostics)
            stop = threading.Event()
            commander = threading.Thread(target=command_loop, args=(rospy, stop), daemon=True)
            commander.start()
            time.sleep(2.0)
            cases = [('nobody watching', []),
                     ('right hand, compressed', [(CAMERAS[-1], interface.CAMERA_COMPRESSED,
                                                  CompressedImage)]),
                     ('3 cameras, compressed', [(c, interface.CAMERA_COMPRESSED, CompressedImage)
                                                for c in CAMERAS]),
                     ('3 cameras, raw bgr8', [(c, interface.CAMERA_IMAGE, Image) for c in CAMERAS])]
            print('nodes at ~rate %g Hz, sim_cameras at nice +%d, arms swinging (%g s per case):'
                  % (RATE_HZ, nice, window_s))
            for title, topics in cases:
                delivered, rendered, cpu = measure(rospy, cams, topics, window_s, newest)
                frames_hz = sum(delivered.values())
                print('  %-24s sim_cameras CPU %5.1f %% of one core%s (load average %.1f)' % (
                    title, cpu, ', %.1f ms CPU a frame' % (10.0 * cpu / frames_hz)
                    if frames_hz else '', os.getloadavg()[0]))
                for camera in sorted(delivered):
                    print('    %-18s delivered %5.1f frames/s, rendered %5.1f frames/s'
                          % (camera, delivered[camera], rendered.get(camera, float('nan'))))
            stop.set()
            rospy.signal_shutdown('benchmark done')
        finally:
            stop_process(cams)
            stop_process(sim)
            log.close()


if __name__ == '__main__':
    main()
