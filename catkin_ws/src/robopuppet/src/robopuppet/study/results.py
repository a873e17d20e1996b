"""A study's result files: trials.csv and questionnaire.csv, appended one whole row at a time.

Pure (files only). Each append writes the header when the file is new or empty, then the row,
flushed and synced, so that a crash loses at most the row being written; a line that a crash
left cut off is dropped before the next append, so the file holds whole lines only.
"""
import csv
import io
import os
import re

TRIALS_CSV = 'trials.csv'
QUESTIONNAIRE_CSV = 'questionnaire.csv'
TRIAL_COLUMNS = ('study', 'participant', 'device', 'task', 'trial', 'practice', 'seed', 'started',
                 'success', 'completion_s', 'path_m', 'jerk', 'zone_s', 'clutches', 'idle_s',
                 'episode')
TLX_COLUMNS = ('tlx_mental', 'tlx_physical', 'tlx_temporal', 'tlx_performance', 'tlx_effort',
               'tlx_frustration')  # NASA-TLX's six scales, in questionnaire.TLX_SCALES' order
SUS_COLUMNS = tuple('sus_%d' % k for k in range(1, 11))
QUESTIONNAIRE_COLUMNS = ('participant', 'device') + TLX_COLUMNS + ('tlx',) + SUS_COLUMNS + (
    'sus',)
PARTICIPANT_RE = re.compile(r'[A-Za-z0-9_-]{1,40}\Z')


class ResultsError(ValueError):
    """A bad participant id, or a results file whose header is not the expected one."""


def check_participant(participant):
    """Return the participant id, or raise ResultsError saying what an id may hold."""
    if not isinstance(participant, str) or not PARTICIPANT_RE.match(participant):
        raise ResultsError('bad participant id %r: use 1 to 40 letters, digits, - or _'
                           % (participant,))
    return participant


def default_results_dir(ros_home, study):
    """Return $ROS_HOME/robopuppet/studies/<study> (ros_home: ROS_HOME, or ~/.ros)."""
    return os.path.join(ros_home, 'robopuppet', 'studies', study)


def _cell(value):
    """Return a CSV cell: booleans as true/false, floats with 4 decimals, None empty."""
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, float):
        return '%.4f' % value
    return '' if value is None else str(value)


def _drop_cut_line(handle):
    """Truncate a file (open for r+b) after its last newline; return its size then."""
    size = handle.seek(0, os.SEEK_END)
    if size == 0:
        return 0
    handle.seek(max(0, size - 65536))
    tail = handle.read()
    if tail.endswith(b'\n'):
        return size
    cut = tail.rfind(b'\n')
    keep = size - len(tail) + cut + 1 if cut >= 0 else (0 if size <= 65536 else size)
    handle.truncate(keep)
    return keep


def append_row(path, columns, row):
    """Append one row (a dict with every column) to a CSV file, the header first when the file
    is new or empty; flushed and synced before it returns.

    Raises:
        ResultsError: the row lacks a column, or the file's header is another one.
        OSError: the file cannot be written.
    """
    missing = [c for c in columns if c not in row]
    if missing:
        raise ResultsError('row without %s' % ', '.join(missing))
    text = io.StringIO()
    writer = csv.writer(text, lineterminator='\n')
    directory = os.path.dirname(path)
    if directory:
        os.makedirs(directory, exist_ok=True)
    with open(path, 'a+b') as handle:
        handle.seek(0)
        header = handle.readline().decode('utf-8', 'replace').rstrip('\n')
        if _drop_cut_line(handle) == 0:
            writer.writerow(columns)
        elif header != ','.join(columns):
            raise ResultsError('%s has another header: %s' % (path, header))
        writer.writerow([_cell(row[c]) for c in columns])
        handle.seek(0, os.SEEK_END)
        handle.write(text.getvalue().encode('utf-8'))
        handle.flush()
        os.fsync(handle.fileno())


def read_rows(path):
    """Return a CSV file's rows as dicts ([] when there is no file); rows without every column
    (a line cut by a crash) are left out."""
    try:
        with open(path, newline='', encoding='utf-8') as handle:
            reader = csv.DictReader(handle)
            return [row for row in reader
                    if None not in row and all(v is not None for v in row.values())]
    except FileNotFoundError:
        return []


def participants(results_dir):
    """Return the study's participant ids in the order they first appear in its trials.csv."""
    seen = []
    for row in read_rows(os.path.join(results_dir, TRIALS_CSV)):
        if row['participant'] not in seen:
            seen.append(row['participant'])
    return seen


def participant_index(results_dir, participant):
    """Return a participant's 0-based index in the study: their place among those seen, or the
    next one for a new participant."""
    seen = participants(results_dir)
    return seen.index(participant) if participant in seen else len(seen)
