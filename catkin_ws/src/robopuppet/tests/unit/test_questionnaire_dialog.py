"""pytest-qt tests of the questionnaire dialog: its defaults, Submit hands on exactly what was
answered, an incomplete SUS is refused with a message and nothing is sent."""
import os

os.environ.setdefault('QT_QPA_PLATFORM', 'offscreen')

import pytest  # noqa: E402
from PyQt5 import QtWidgets  # noqa: E402

from robopuppet.gui.questionnaire_dialog import QuestionnaireDialog  # noqa: E402
from robopuppet.study import questionnaire  # noqa: E402

TLX = [0.0, 35.0, 100.0, 5.0, 60.0, 95.0]
SUS = [4, 2, 5, 1, 3, 2, 5, 1, 4, 3]


@pytest.fixture
def dialog(qtbot):
    sent = []
    window = QuestionnaireDialog('P07', 'gamepad', lambda *answers: sent.append(answers))
    window.sent = sent
    qtbot.addWidget(window)
    window.show()
    return window


def answer(dialog, tlx, sus):
    """Move the sliders (in their steps of 5) and click the radio buttons as a participant does."""
    for slider, rating in zip(dialog.sliders, tlx):
        slider.setValue(int(rating) // questionnaire.TLX_STEP)
    for group, value in zip(dialog.answer_groups, sus):
        if value is not None:
            group.button(value).click()


def test_the_form_starts_at_the_middle_of_each_scale_with_no_statement_answered(dialog):
    assert len(dialog.sliders) == 6 and len(dialog.answer_groups) == 10
    assert dialog.answers() == ([50.0] * 6, [None] * 10)
    assert [label.text() for label in dialog.value_labels] == ['50'] * 6
    low, high = dialog.sliders[0].minimum(), dialog.sliders[0].maximum()
    assert (low * questionnaire.TLX_STEP, high * questionnaire.TLX_STEP) == (0, 100)
    assert high - low + 1 == 21   # 0, 5, ..., 100: nothing between the steps
    assert 'gamepad' in dialog.windowTitle() and 'P07' in dialog.windowTitle()


def test_submit_hands_on_exactly_the_answers_and_closes(dialog):
    answer(dialog, TLX, SUS)
    assert [label.text() for label in dialog.value_labels] == ['0', '35', '100', '5', '60', '95']
    dialog.submit_button.click()
    assert dialog.sent == [('P07', 'gamepad', TLX, SUS)]
    assert dialog.result() == QtWidgets.QDialog.Accepted and not dialog.isVisible()


def test_a_changed_answer_counts_its_last_choice(dialog):
    answer(dialog, TLX, SUS)
    dialog.answer_groups[0].button(1).click()
    dialog.sliders[5].setValue(2)
    dialog.submit_button.click()
    assert dialog.sent == [('P07', 'gamepad', TLX[:5] + [10.0], [1] + SUS[1:])]


def test_an_incomplete_sus_is_refused_with_a_message_and_nothing_is_sent(dialog):
    answer(dialog, TLX, SUS[:6] + [None] + SUS[7:])
    dialog.submit_button.click()
    assert dialog.sent == []
    assert dialog.isVisible()
    assert dialog.message_label.text() == (
        'SUS statement 7 is not answered: please answer every statement.')
    dialog.answer_groups[6].button(5).click()
    dialog.submit_button.click()
    assert dialog.sent == [('P07', 'gamepad', TLX, SUS[:6] + [5] + SUS[7:])]


def test_later_closes_without_sending(dialog):
    answer(dialog, TLX, SUS)
    dialog.reject()
    assert dialog.sent == [] and dialog.result() == QtWidgets.QDialog.Rejected
