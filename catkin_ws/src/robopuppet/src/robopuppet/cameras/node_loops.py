"""The two loops of a camera node (camera, sim_cameras), run until ROS shuts down: its frames at
its rate and its /diagnostics at 1 Hz, both through one Guard (periodic), so that a failed frame
or report is logged and the next one comes as usual; and sim_cameras' status."""
import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from robopuppet import interface
from robopuppet.periodic import Guard, Loop

DIAGNOSTICS_PERIOD_S = 1.0
STOP_TIMEOUT_S = 2.0  # per loop, at shutdown


def spin(what, rate_hz, tick, diagnose, release=None):
    """Call tick() at rate_hz and publish diagnose()'s DiagnosticStatus on /diagnostics every
    DIAGNOSTICS_PERIOD_S until shutdown.

    At shutdown both loops stop (each waited for up to STOP_TIMEOUT_S), then release() (if
    given) frees what the frames came from.

    Args:
        what: the frame loop's name, for log lines and its thread.
    """
    diagnostics = rospy.Publisher(interface.DIAGNOSTICS, DiagnosticArray, queue_size=10)

    def report():
        array = DiagnosticArray(status=[diagnose()])
        array.header.stamp = rospy.Time.now()
        diagnostics.publish(array)
    guard = Guard(rospy.get_name(), rospy.logerr)
    loops = [Loop(guard, what, 1.0 / rate_hz, tick),
             Loop(guard, 'camera diagnostics', DIAGNOSTICS_PERIOD_S, report)]

    def stop():
        for loop in loops:
            loop.stop(STOP_TIMEOUT_S)
        if release is not None:
            release()
    rospy.on_shutdown(stop)
    for loop in loops:
        loop.start()
    rospy.spin()


def render_status(name, cameras, per_s):
    """Return sim_cameras' DiagnosticStatus: frames/s rendered and published per camera (per_s:
    {(camera, 'rendered' or 'published'): frames/s}, frame_rates.FrameRates.read's)."""
    values, lines = [], []
    for camera in cameras:
        render_hz, publish_hz = per_s[camera, 'rendered'], per_s[camera, 'published']
        values += [KeyValue('%s rendered_hz' % camera, '%.1f' % render_hz),
                   KeyValue('%s published_hz' % camera, '%.1f' % publish_hz)]
        if publish_hz > 0.0:
            lines.append('%s %.1f/s' % (camera, publish_hz))
    return DiagnosticStatus(
        level=DiagnosticStatus.OK, name='%s: simulated cameras' % name,
        message='publishing ' + ', '.join(lines) if lines else 'nobody watches',
        hardware_id='simulated', values=values)
