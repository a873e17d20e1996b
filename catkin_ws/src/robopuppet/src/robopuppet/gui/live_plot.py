"""Scrolling time plots: the newest sample at the right edge (time 0), older ones to the left."""
import numpy as np
import pyqtgraph as pg
from PyQt5 import QtCore  # pyqtgraph uses PyQt5: see robopuppet.gui's PYQTGRAPH_QT_LIB


class Series:
    """The last `window_s` seconds of one signal, at most `capacity` points (numpy arrays)."""

    def __init__(self, window_s, capacity=2048):
        self.window_s = window_s
        self.capacity = capacity
        self.times_s = np.empty(0)
        self.values = np.empty(0)

    def extend(self, points):
        """Append [(time s, value), ...] (in time order) and forget what is out of the window."""
        if not points:
            return
        new = np.asarray(points, dtype=float)
        times = np.concatenate((self.times_s, new[:, 0]))[-self.capacity:]
        values = np.concatenate((self.values, new[:, 1]))[-self.capacity:]
        keep = times >= times[-1] - self.window_s
        # Keep one point before the window so that a step curve reaches the left edge.
        first = max(int(np.argmax(keep)) - 1, 0)
        self.times_s, self.values = times[first:], values[first:]

    def relative(self, now_s):
        """Return (times relative to now_s in s, values); times are <= 0 for past samples."""
        return self.times_s - now_s, self.values

    def steps(self, now_s):
        """Return the series as a step curve held until now_s: (relative times, values)."""
        if not len(self.values):
            return self.times_s, self.values
        times = np.append(np.repeat(self.times_s, 2)[1:], now_s)
        values = np.repeat(self.values, 2)
        return times - now_s, values


class LivePlot(pg.PlotWidget):
    """A plot of named curves over the last `window_s` seconds, redrawn by `refresh(now_s)`.

    Args:
        title: plot title, e.g. 'angle'.
        unit: unit of the y axis, e.g. 'rad'.
        curves: [(name, colour, step)]: step curves hold their value until the next sample
            (setpoints); other curves join samples with lines.
    """

    def __init__(self, title, unit, curves, window_s=10.0, parent=None):
        super().__init__(parent=parent)
        self.window_s = window_s
        self.series = {}
        self._curves = {}
        self._step = {}
        item = self.getPlotItem()
        item.setTitle(title)
        item.setLabel('left', unit)
        item.setLabel('bottom', 'time (s)')
        item.showGrid(x=True, y=True, alpha=0.3)
        item.addLegend(offset=(5, 5))
        item.setMouseEnabled(x=False, y=True)
        item.setXRange(-window_s, 0, padding=0)
        item.enableAutoRange(axis='y')
        item.setClipToView(True)
        for name, colour, step in curves:
            style = QtCore.Qt.DashLine if step else QtCore.Qt.SolidLine
            pen = pg.mkPen(colour, width=2, style=style)
            self._curves[name] = item.plot(name=name, pen=pen, connect='finite')
            self.series[name] = Series(window_s)
            self._step[name] = step

    def extend(self, name, points):
        """Append [(time s, value), ...] to curve `name` (cheap; does not redraw)."""
        self.series[name].extend(points)

    def refresh(self, now_s):
        """Redraw every curve relative to now_s."""
        for name, curve in self._curves.items():
            series = self.series[name]
            times, values = series.steps(now_s) if self._step[name] else series.relative(now_s)
            curve.setData(times, values)
