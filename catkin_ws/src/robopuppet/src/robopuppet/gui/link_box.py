"""The "Link to the robot room" box of the main tab: what link_view.describe decides, coloured."""
from PyQt5 import QtWidgets

from robopuppet.gui import freshness, link_view
from robopuppet.gui.look import AMBER, GREEN, RED

LEVEL_COLOUR = {link_view.OK: GREEN, link_view.WARN: AMBER, link_view.ERROR: RED}
STATUS_STYLE = 'QLabel { background: %s; padding: 3px; border-radius: 3px; }'
STATUS_LINES = 3  # room kept for the status (link_view.STATUS_MAX_CHARS): the tab does not jump


class LinkBox(QtWidgets.QGroupBox):
    """A coloured status line, then round trip, delay to Baxter, pings lost and where the fault is.

    A status cut short shows all of it as its tooltip. The last line says how old the newest
    link_state is; once it is not current, the figures are greyed (they show '—'). refresh(snap, now_s) once per frame on
    the GUI thread; nothing here talks to ROS.
    """

    def __init__(self, parent=None):
        super().__init__('Link to the robot room', parent)
        self.status_label = QtWidgets.QLabel()
        self.status_label.setWordWrap(True)
        self.status_label.setMinimumHeight(
            STATUS_LINES * self.status_label.fontMetrics().lineSpacing() + 8)  # + padding
        self.rtt_label = QtWidgets.QLabel()
        self.delay_label = QtWidgets.QLabel()
        self.delay_label.setWordWrap(True)
        self.loss_label = QtWidgets.QLabel()
        self.where_label = QtWidgets.QLabel()
        self.where_label.setWordWrap(True)
        self.age_label = QtWidgets.QLabel()
        for label in (self.rtt_label, self.loss_label, self.age_label):
            label.setWordWrap(True)
        layout = QtWidgets.QVBoxLayout(self)
        for label in (self.status_label, self.rtt_label, self.delay_label, self.loss_label,
                      self.where_label, self.age_label):
            layout.addWidget(label)
        layout.addStretch(1)
        self.view = None

    def refresh(self, snap, now_s):
        """Show the link as of a state.Snapshot taken at now_s (s)."""
        view = link_view.describe(snap, now_s)
        received_s = None if snap.robot_link is None else snap.robot_link.received_s
        stale = freshness.is_stale(received_s, now_s, freshness.LINK_STALE_S)
        self.age_label.setText(freshness.age_text(received_s, now_s, freshness.LINK_STALE_S,
                                                  'link_state'))
        style = 'QLabel { color: %s; }' % freshness.STALE_TEXT_COLOUR
        for label in (self.rtt_label, self.delay_label, self.loss_label, self.age_label):
            if label.styleSheet() != (style if stale or label is self.age_label else ''):
                label.setStyleSheet(style if stale or label is self.age_label else '')
        if view == self.view:
            return  # unchanged: no relayout at 30 frames/s
        self.view = view
        self.status_label.setText(view.status)
        self.status_label.setToolTip(view.full_status if view.full_status != view.status else '')
        self.status_label.setStyleSheet(STATUS_STYLE % LEVEL_COLOUR[view.level])
        self.rtt_label.setText(view.rtt)
        self.delay_label.setText(view.delay)
        self.loss_label.setText(view.loss)
        self.where_label.setText(view.where)
