"""train_assist's plot (--plot): one held-out demonstration's follower motion, demonstrated and
predicted, joint by joint and the gripper, shaded where the prediction was unfamiliar.

Pure (numpy, matplotlib through png_plot: no display needed, imported where the figure is
made, so that training without --plot starts sooner).
"""
import numpy as np

from robopuppet import png_plot
from robopuppet.assist import learners
from robopuppet.baxter_description import arm_joint_names


def unfamiliar_spans(t, familiar):
    """Return [(start s, end s)] of the runs of steps not familiar (end: the run's last step
    plus one step)."""
    step = float(np.median(np.diff(t))) if len(t) > 1 else 0.0
    spans, start = [], None
    for k, ok in enumerate(familiar):
        if not ok and start is None:
            start = t[k]
        if ok and start is not None:
            spans.append((start, t[k]))
            start = None
    if start is not None:
        spans.append((start, t[-1] + step))
    return spans


def plot_figure(predictor, demo, title):
    """Return the figure (matplotlib): 9 panels over time, the follower's 7 joints (deg) and
    its gripper (closed 1, open 0), demonstrated and predicted, and the confidence; red
    shading where the prediction is unfamiliar."""
    plt = png_plot.pyplot()
    positions, closed, confidence = predictor.predict_demo(demo)
    shown, shown_closed = learners.arm(demo, predictor.follower)
    spans = unfamiliar_spans(demo.t, confidence >= learners.CONFIDENCE_THRESHOLD)
    figure, axes = plt.subplots(9, 1, sharex=True, figsize=(10, 16))
    figure.suptitle(title)
    names = arm_joint_names(predictor.follower)
    for j, axis in enumerate(axes[:7]):
        axis.plot(demo.t, np.degrees(shown[:, j]), 'k-', label='demonstrated')
        axis.plot(demo.t, np.degrees(positions[:, j]), 'C1--', label='predicted')
        axis.set_ylabel('%s\n(deg)' % names[j])
    axes[7].step(demo.t, shown_closed.astype(float), 'k-', where='post', label='demonstrated')
    axes[7].step(demo.t, closed.astype(float), 'C1--', where='post', label='predicted')
    axes[7].set_ylabel('gripper\nclosed')
    axes[8].plot(demo.t, confidence, 'C2-', label='confidence')
    axes[8].axhline(learners.CONFIDENCE_THRESHOLD, color='r', lw=0.8, label='threshold')
    axes[8].set_ylim(-0.05, 1.05)
    axes[8].set_ylabel('confidence')
    axes[8].set_xlabel('time (s)')
    for axis in axes:
        for start, end in spans:
            axis.axvspan(start, end, color='r', alpha=0.15, lw=0)
    axes[0].legend(loc='lower left', bbox_to_anchor=(0, 1.02), ncol=3, fontsize='small')
    axes[8].legend(loc='upper right', fontsize='small')
    return figure


def write_plot(path, predictor, demo, title):
    """Write plot_figure's figure as a PNG."""
    png_plot.write_png(path, plot_figure(predictor, demo, title))
