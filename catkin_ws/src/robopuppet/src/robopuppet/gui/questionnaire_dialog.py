"""The questionnaire dialog after each device of a study: NASA-TLX (six sliders 0..100 in steps
of 5) and SUS (ten statements, 1..5); Submit checks the answers (study.questionnaire) and hands
them on; an incomplete form is refused with a message and nothing is sent."""
from PyQt5 import QtCore, QtWidgets

from robopuppet.study import questionnaire

TLX_DEFAULT = 50   # each slider starts in the middle: the participant moves it (or agrees)
RED_TEXT = 'QLabel { color: #c62828; font-weight: bold; }'


class QuestionnaireDialog(QtWidgets.QDialog):
    """Ask one participant about one device; on a complete Submit call
    submit(participant, device, tlx, sus) and close.

    Args:
        participant: the participant's id; device: the device the answers are about.
        submit: called with the six TLX ratings (float) and the ten SUS answers (int).
    """

    def __init__(self, participant, device, submit, parent=None):
        super().__init__(parent)
        self.participant, self.device = participant, device
        self._submit = submit
        self.setWindowTitle('Questionnaire: %s, participant %s' % (device, participant))
        intro = QtWidgets.QLabel(
            'About the %s you just used ("the system" below). Part 1: drag each slider to where '
            'the task put you. Part 2: answer every statement.' % device)
        intro.setWordWrap(True)
        self.sliders = []
        self.value_labels = []
        tlx = QtWidgets.QGroupBox('Part 1: workload (NASA-TLX)')
        grid = QtWidgets.QGridLayout(tlx)
        for row, scale in enumerate(questionnaire.TLX_SCALES):
            slider = QtWidgets.QSlider(QtCore.Qt.Horizontal)
            step = questionnaire.TLX_STEP
            slider.setRange(questionnaire.TLX_MIN // step, questionnaire.TLX_MAX // step)
            slider.setPageStep(2)
            slider.setTickPosition(QtWidgets.QSlider.TicksBelow)
            slider.setValue(TLX_DEFAULT // step)
            value = QtWidgets.QLabel()
            value.setMinimumWidth(value.fontMetrics().horizontalAdvance('100') + 4)
            slider.valueChanged.connect(lambda v, label=value: label.setText(str(v * step)))
            value.setText(str(slider.value() * step))
            name = QtWidgets.QLabel('<b>%s</b>: %s' % (scale.name, scale.question))
            name.setWordWrap(True)
            grid.addWidget(name, 2 * row, 0, 1, 4)   # the question above its slider
            grid.addWidget(QtWidgets.QLabel(scale.low), 2 * row + 1, 0, QtCore.Qt.AlignRight)
            grid.addWidget(slider, 2 * row + 1, 1)
            grid.addWidget(QtWidgets.QLabel(scale.high), 2 * row + 1, 2)
            grid.addWidget(value, 2 * row + 1, 3)
            self.sliders.append(slider)
            self.value_labels.append(value)
        grid.setColumnStretch(1, 1)
        self.answer_groups = []
        sus = QtWidgets.QGroupBox('Part 2: usability (SUS): 1 %s .. 5 %s' % (
            questionnaire.SUS_ANCHORS[0], questionnaire.SUS_ANCHORS[-1]))
        grid = QtWidgets.QGridLayout(sus)
        for column, anchor in enumerate(questionnaire.SUS_ANCHORS, 1):
            head = QtWidgets.QLabel(str(column))
            head.setToolTip(anchor)
            head.setAlignment(QtCore.Qt.AlignCenter)
            grid.addWidget(head, 0, column)
            grid.setColumnMinimumWidth(column, 32)   # a finger's width between the choices
        for row, statement in enumerate(questionnaire.SUS_ITEMS, 1):
            label = QtWidgets.QLabel('%d. %s' % (row, statement))
            label.setWordWrap(True)
            grid.addWidget(label, row, 0)
            group = QtWidgets.QButtonGroup(self)
            for answer in range(questionnaire.SUS_MIN, questionnaire.SUS_MAX + 1):
                radio = QtWidgets.QRadioButton()
                radio.setToolTip(questionnaire.SUS_ANCHORS[answer - 1])
                group.addButton(radio, answer)
                grid.addWidget(radio, row, answer, QtCore.Qt.AlignCenter)
            self.answer_groups.append(group)
        grid.setColumnStretch(0, 1)
        self.message_label = QtWidgets.QLabel()
        self.message_label.setWordWrap(True)
        self.message_label.setStyleSheet(RED_TEXT)
        self.submit_button = QtWidgets.QPushButton('Submit')
        self.submit_button.setDefault(True)
        self.submit_button.clicked.connect(self.submit)
        later = QtWidgets.QPushButton('Later')
        later.setToolTip('Close the form; the study tab opens it again')
        later.clicked.connect(self.reject)
        buttons = QtWidgets.QHBoxLayout()
        buttons.addWidget(self.message_label, 1)
        buttons.addWidget(later)
        buttons.addWidget(self.submit_button)
        inner = QtWidgets.QWidget()
        columns = QtWidgets.QHBoxLayout(inner)   # side by side: no scrolling on 1280 x 760
        columns.addWidget(tlx, 5)
        columns.addWidget(sus, 6)
        scroll = QtWidgets.QScrollArea()   # a smaller screen scrolls
        scroll.setWidgetResizable(True)
        scroll.setFrameShape(QtWidgets.QFrame.NoFrame)
        scroll.setWidget(inner)
        layout = QtWidgets.QVBoxLayout(self)
        layout.addWidget(intro)
        layout.addWidget(scroll, 1)
        layout.addLayout(buttons)
        self.resize(1260, 700)

    def answers(self):
        """Return (tlx, sus): the six ratings (0..100) and the ten answers (1..5, None where a
        statement is not answered)."""
        tlx = [float(slider.value() * questionnaire.TLX_STEP) for slider in self.sliders]
        sus = [group.checkedId() if group.checkedId() > 0 else None
               for group in self.answer_groups]
        return tlx, sus

    def submit(self):
        """Hand complete answers on and close; else say what is missing and send nothing."""
        tlx, sus = self.answers()
        why = questionnaire.check_answers(tlx, sus)
        if why:
            self.message_label.setText('%s: please answer every statement.' % why)
            return
        self.message_label.setText('')
        self._submit(self.participant, self.device, tlx, sus)
        self.accept()
