"""Unit tests of calibrate's terminal prompts (calibration.prompt) on piped input."""
import io

from robopuppet.calibration import prompt


def test_a_typed_line_is_stripped_and_lower_case_and_the_end_of_input_quits():
    out = io.StringIO()
    assert prompt.ask('Store? ', io.StringIO('  Y \n'), out) == 'y'
    assert out.getvalue() == 'Store? '
    out = io.StringIO()
    assert prompt.ask('Store? ', io.StringIO(''), out) == 'q'
    assert out.getvalue() == 'Store? \n'


def test_piped_input_gets_the_plain_prompt_without_the_live_line():
    out = io.StringIO()
    assert prompt.ask_live('Pose: ', lambda: 'live', io.StringIO('R\n'), out) == 'r'
    assert out.getvalue() == 'Pose: '
    assert prompt.ask_live('Pose: ', lambda: 'live', io.StringIO(''), io.StringIO()) == 'q'
