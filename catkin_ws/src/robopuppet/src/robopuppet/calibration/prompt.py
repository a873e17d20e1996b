"""The terminal side of `calibrate`: its help text and prompts with a live readout.

No ROS: the readout is a function the caller passes (it reads the latest angles).
"""
import select
import sys

KEYS_AND_EXIT_CODES = """\
keys, while a pose is awaited (type the letter, then Enter):
  Enter  capture the pose (the angles the puppet reports now)
  r      take the previous pose again
  p      pose the virtual puppet so (only with the simulated puppet, sim_puppet:=true)
  q      quit: nothing stored
While it waits, the line above the prompt shows the reported angles live (on a terminal).

exit status:
  0  stored (or --dry-run)
  1  quit, Ctrl-C, end of input, no ROS master, or no puppet (config_X, serial_X) answering
  2  a joint flagged: capture its poses again (nothing stored)
  3  the store failed: nothing stored, every joint keeps its old values
"""
REFRESH_S = 0.2  # how often the live readout is redrawn


def ask(prompt, stdin=None, stdout=None):
    """Return a line typed by the operator (stripped, lower case), or 'q' at the end of input."""
    stdin, stdout = stdin or sys.stdin, stdout or sys.stdout
    stdout.write(prompt)
    stdout.flush()
    return _answer(stdin, stdout)


def ask_live(prompt, live, stdin=None, stdout=None):
    """Like ask, but on a terminal redraw `live()` (one line of text) every REFRESH_S above the
    prompt until a line is typed. Piped input gets the plain prompt."""
    stdin, stdout = stdin or sys.stdin, stdout or sys.stdout
    if not (stdin.isatty() and stdout.isatty()):
        return ask(prompt, stdin, stdout)
    stdout.write('%s\n%s' % (live(), prompt))
    stdout.flush()
    while not select.select([stdin], [], [], REFRESH_S)[0]:
        # Up one line, redraw it, back down to the end of the prompt; what is typed stays.
        stdout.write('\x1b7\x1b[1A\r%s\x1b[K\x1b8' % live())
        stdout.flush()
    return _answer(stdin, stdout)


def _answer(stdin, stdout):
    """Read the typed line: stripped, lower case; 'q' (after a newline) at the end of input."""
    line = stdin.readline()
    if not line:
        stdout.write('\n')
        return 'q'
    return line.strip().lower()
