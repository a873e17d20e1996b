"""The one way the rostest scripts wait: for an event, never for a fixed time."""
import time

import rospy


def wait_for(condition, timeout_s, what=None, step_s=0.02):
    """Poll condition() every step_s until it returns something true, for at most timeout_s.

    Returns:
        condition()'s last value: true once it held, false after the timeout (or when ROS
        shuts down).
    Raises:
        AssertionError naming `what` on a timeout, when `what` is given.
    """
    deadline = time.monotonic() + timeout_s
    while True:
        result = condition()
        if result or time.monotonic() > deadline or rospy.is_shutdown():
            break
        time.sleep(step_s)
    if not result and what is not None:
        raise AssertionError('timed out after %.1f s waiting for %s' % (timeout_s, what))
    return result


def seconds_until(condition, timeout_s, step_s=0.02):
    """Return how many seconds condition() took to hold (polled every step_s); None on timeout."""
    start = time.monotonic()
    return time.monotonic() - start if wait_for(condition, timeout_s, step_s=step_s) else None
