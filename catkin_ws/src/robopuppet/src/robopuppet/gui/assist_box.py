"""The main tab's Assist box: what robopuppet's assist node does (its AssistState), in colour,
its confidence, Stop assist / Start assist, and how to take its arm over with a puppet.

Hidden until an AssistState arrives; greyed "NOT CURRENT" once none came for ASSIST_STALE_S.
describe() decides what shows (pure); AssistBox only draws it.
"""
import collections

from PyQt5 import QtWidgets

from robopuppet.gui import freshness
from robopuppet.gui.look import AMBER, GREEN, GREY, paint, restyle, show_age
from robopuppet.interface import BUTTON_LEFT, BUTTON_RIGHT

# The assist node publishes its state on every change and at least every 0.5 s: three missed.
ASSIST_STALE_S = 1.5
STATE_COLOUR = {'assisting': GREEN, 'holding': AMBER, 'stopped': GREY, 'off': GREY}
TAKE_OVER = {'left': ('L', BUTTON_LEFT), 'right': ('R', BUTTON_RIGHT)}  # follower -> puppet

View = collections.namedtuple('View', 'summary state colour detail detail_colour confidence_pct '
                                      'hint can_start can_stop stale')
View.__doc__ = """What the box shows: the summary line, the state line and its colour ('' plain),
the detail and its colour, the confidence (0-100 %), the take-over hint, whether Start assist
and Stop assist are enabled, and whether the state is not current."""


def describe(assist, now_s):
    """Return the View of a state_topics.Assist at now_s (s)."""
    stale = freshness.is_stale(assist.received_s, now_s, ASSIST_STALE_S)
    about = ', '.join(filter(None, (assist.task, assist.method)))
    summary = "Assist: Baxter's %s arm, from the %s arm's motion%s" % (
        assist.follower or '?', assist.leader or '?', ' (%s)' % about if about else '')
    puppet, button = TAKE_OVER.get(assist.follower, ('?', '?'))
    colour = GREY if stale else STATE_COLOUR.get(assist.state, '')
    holding = assist.state == 'holding' and not stale
    return View(summary, 'assist: %s%s' % (assist.state, '   NOT CURRENT' if stale else ''),
                colour, assist.detail, AMBER if holding else '',
                int(round(100.0 * min(max(assist.confidence, 0.0), 1.0))),
                'take over: press %s on puppet %s' % (button, puppet),
                assist.state == 'stopped' and not stale, assist.state != 'stopped' or stale,
                stale)   # a stop never hurts: not knowing the state, Stop stays at hand


class AssistBox(QtWidgets.QGroupBox):
    """The assist's state, confidence bar, detail, Stop/Start buttons and take-over hint.

    Args:
        client: a PuppetClient (or a test double) with assist_state() (gui.assist_topics) and
            command_assist() (gui.command_topics);
            a client without assist_state() never shows the box.
    refresh(now_s) once per frame on the GUI thread.
    """

    def __init__(self, client, parent=None):
        super().__init__('Assist', parent)
        self._client = client
        self.summary_label = QtWidgets.QLabel()
        self.state_label = QtWidgets.QLabel()
        self.detail_label = QtWidgets.QLabel()
        self.hint_label = QtWidgets.QLabel()
        self.age_label = QtWidgets.QLabel()
        for label in (self.summary_label, self.detail_label, self.age_label):
            label.setWordWrap(True)
        self.confidence_bar = QtWidgets.QProgressBar()
        self.confidence_bar.setRange(0, 100)
        self.confidence_bar.setFormat('confidence %p%')
        self.confidence_bar.setMinimumWidth(   # its text on one line
            self.confidence_bar.fontMetrics().horizontalAdvance('confidence 100%') + 30)
        self.stop_button = QtWidgets.QPushButton('Stop assist')
        self.start_button = QtWidgets.QPushButton('Start assist')
        self.stop_button.clicked.connect(lambda: self._client.command_assist('stop'))
        self.start_button.clicked.connect(lambda: self._client.command_assist('start'))
        row = QtWidgets.QHBoxLayout()
        for widget, stretch in ((self.state_label, 1), (self.confidence_bar, 1),
                                (self.stop_button, 0), (self.start_button, 0)):
            row.addWidget(widget, stretch)
        rows = QtWidgets.QVBoxLayout(self)
        rows.addWidget(self.summary_label)
        rows.addLayout(row)
        for label in (self.detail_label, self.hint_label, self.age_label):
            rows.addWidget(label)
        self.view = None
        self.setVisible(False)

    def refresh(self, now_s):
        """Show the assist's latest state as of now_s (s); hidden while there is none."""
        assist = self._client.assist_state() if hasattr(self._client, 'assist_state') else None
        if assist is None:
            self.setVisible(False)
            return
        self.setVisible(True)
        show_age(self.age_label, assist.received_s, now_s, ASSIST_STALE_S, 'assist')
        view = describe(assist, now_s)
        if view == self.view:
            return   # unchanged: no relayout at 30 frames/s
        self.view = view
        self.summary_label.setText(view.summary)
        self.state_label.setText(view.state)
        if view.colour:
            paint(self.state_label, view.colour)
        else:
            restyle(self.state_label, '')
        self.detail_label.setText(view.detail)
        if view.detail_colour:
            paint(self.detail_label, view.detail_colour)
        else:
            restyle(self.detail_label, 'QLabel { color: %s; }' % freshness.STALE_TEXT_COLOUR
                    if view.stale else '')
        self.confidence_bar.setValue(view.confidence_pct)
        self.confidence_bar.setEnabled(not view.stale)
        self.hint_label.setText(view.hint)
        self.hint_label.setVisible(view.hint not in view.detail)   # said once is enough
        self.start_button.setEnabled(view.can_start)
        self.stop_button.setEnabled(view.can_stop)
