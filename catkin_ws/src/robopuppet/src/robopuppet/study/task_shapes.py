"""What RViz (and the simulated cameras) show of a trial: shapes and lines, no messages.

task_shapes(judge) gives world.shapes Shapes with their colours: each goal now as a translucent
sphere of its position tolerance (green while met, amber before), the pick_place spots as flat
discs, the object (a 4 cm cube) and the bimanual tray (a board between its handles) where they
are now. task_lines(judge) gives the trace's path through its waypoints. study.task_markers
makes them a MarkerArray. Pure.
"""
from robopuppet.world.shapes import Shape

GOAL_RGBA = (1.0, 0.65, 0.0, 0.5)       # amber: to reach
REACHED_RGBA = (0.1, 0.85, 0.2, 0.6)    # green: met now
SPOT_RGBA = {'grasp': (0.2, 0.4, 1.0, 0.8), 'release': (0.6, 0.2, 0.9, 0.8)}
OBJECT_RGBA = (0.95, 0.85, 0.1, 1.0)
PATH_RGBA = (1.0, 1.0, 1.0, 0.8)
OBJECT_SIZE_M = 0.04
SPOT_THICKNESS_M = 0.004
TRAY_DEPTH_M, TRAY_THICKNESS_M = 0.12, 0.015


def _sphere(name, xyz, radius, rgba):
    return Shape(name, 'sphere', None, radius, None, tuple(xyz), (0.0, 0.0, 0.0), rgba[:3]), rgba


def task_shapes(judge):
    """Return [(Shape, rgba)] of a trial judged by judge (task_judge.TrialJudge), as it is
    now: the goals to reach, the pick_place spots still to use, its object, the tray."""
    drawn = []
    reached = judge.reached() or [False] * len(judge.goals())
    for n, (goal, met) in enumerate(zip(judge.goals(), reached)):
        drawn.append(_sphere('goal %d' % n, goal.xyz, goal.tolerance_m,
                             REACHED_RGBA if met else GOAL_RGBA))
    if judge.trial.task == 'pick_place':
        for n, stage in enumerate(judge.trial.plan):
            if n < judge.stage:
                continue
            (goal,) = stage.goals
            rgba = SPOT_RGBA[stage.kind]
            centre = (goal.xyz[0], goal.xyz[1], goal.xyz[2] - OBJECT_SIZE_M / 2.0)
            drawn.append((Shape('spot %s' % 'AB'[n], 'cylinder', None, goal.tolerance_m,
                                SPOT_THICKNESS_M, centre, (0.0, 0.0, 0.0), rgba[:3]), rgba))
    for name, xyz in judge.objects():
        if name == 'bimanual':
            size = (TRAY_DEPTH_M, tray_width(judge), TRAY_THICKNESS_M)
        else:
            size = (OBJECT_SIZE_M,) * 3
        drawn.append((Shape(name, 'box', size, None, None, tuple(xyz), (0.0, 0.0, 0.0),
                            OBJECT_RGBA[:3]), OBJECT_RGBA))
    return drawn


def tray_width(judge):
    """Return the distance (m) between the bimanual trial's handles."""
    left, right = judge.trial.plan[0].goals
    return sum((a - b) ** 2 for a, b in zip(left.xyz, right.xyz)) ** 0.5


def task_lines(judge):
    """Return [(name, [xyz, ...], rgba)]: the trace's path from the tip's next waypoint on
    (all of them before the first), nothing for the other tasks or once done."""
    if judge.trial.task != 'trace' or judge.done:
        return []
    points = [stage.goals[0].xyz for stage in judge.trial.plan[max(0, judge.stage - 1):]]
    return [('path', points, PATH_RGBA)] if len(points) > 1 else []
