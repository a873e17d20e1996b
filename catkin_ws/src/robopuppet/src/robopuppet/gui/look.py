"""The GUI's shared look: status colours, numbers as the tables show them, painted labels and the
age line of a value from the robot room (gui.freshness decides what is stale)."""
import math

from robopuppet.gui import freshness

GREEN, AMBER, RED, GREY, BLUE = '#c8e6c9', '#ffe0b2', '#ffcdd2', '#e0e0e0', '#bbdefb'


def number(value, digits=3):
    """Return value with fixed digits, or '—' when it is unknown (NaN)."""
    return '—' if value is None or math.isnan(value) else '%+.*f' % (digits, value)


def paint(widget, colour):
    """Give a label a coloured background."""
    restyle(widget, 'QLabel { background: %s; padding: 3px; border-radius: 3px; }' % colour)


def restyle(widget, style):
    """Set a widget's style sheet unless it has it already (no restyling at 30 frames/s)."""
    if widget.styleSheet() != style:
        widget.setStyleSheet(style)


def grey_out(label, stale):
    """Show a label's text greyed when it is not current, in the normal colour when it is."""
    restyle(label, 'QLabel { color: %s; }' % freshness.STALE_TEXT_COLOUR if stale else '')


def show_age(label, received_s, now_s, limit_s, what):
    """Write the age line of a value from the robot room: plain while current, greyed and
    bold once older than limit_s (freshness)."""
    stale = freshness.is_stale(received_s, now_s, limit_s)
    label.setText(freshness.age_text(received_s, now_s, limit_s, what))
    restyle(label, 'QLabel { background: %s; color: #212121; font-weight: bold; padding: 3px; '
                   'border-radius: 3px; }' % GREY if stale
            else 'QLabel { color: %s; }' % freshness.STALE_TEXT_COLOUR)
    return stale
