"""The LeRobot dataset's Parquet files, written and read with pyarrow: the frames' rows
(data/), the episodes' rows (meta/episodes/) and the tasks (meta/tasks.parquet).

Debian 12 has no Parquet library: tools/setup.sh installs a pinned pyarrow from the Python
package registry into catkin_ws/devel/python-deps (PYARROW_DIR), which pyarrow() finds however
the export is started (rosrun, pytest, a benchmark). Pure (numpy, pyarrow; no ROS).
"""
import json
import os
import sys

import numpy as np

from robopuppet import atomic_file
from robopuppet.episodes import lerobot_meta

PYARROW_VERSION = '17.0.0'  # tools/setup.sh installs this one
PYARROW_DIR = os.environ.get('ROBOPUPPET_PYTHON_DEPS') or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), *(['..'] * 5), 'devel', 'python-deps')
COMPRESSION = 'snappy'  # LeRobot's


class ParquetMissing(ImportError):
    """pyarrow is not installed where the export looks for it."""


def pyarrow():
    """Return the modules (pyarrow, pyarrow.parquet), adding PYARROW_DIR to the path.

    Raises:
        ParquetMissing: not installed: the message names the set-up command.
    """
    try:
        import pyarrow as pa  # pylint: disable=import-outside-toplevel
    except ImportError:
        directory = os.path.normpath(PYARROW_DIR)
        if os.path.isdir(directory) and directory not in sys.path:
            sys.path.append(directory)
        try:
            import pyarrow as pa  # pylint: disable=import-outside-toplevel
        except ImportError as error:
            raise ParquetMissing(
                'the LeRobot export needs pyarrow %s, not found in %s: run tools/setup.sh '
                '(or ./run.sh, ./test.sh), which installs it there' % (
                    PYARROW_VERSION, directory)) from error
    import pyarrow.parquet as pq  # pylint: disable=import-outside-toplevel
    return pa, pq


def data_schema(features):
    """Return the data files' schema: each non-video feature a column, vectors as fixed-size
    lists (what LeRobot's datasets library writes for a Sequence of known length)."""
    pa, _ = pyarrow()
    fields = []
    for name, feature in features.items():
        if feature['dtype'] == 'video':
            continue
        scalar = {'float32': pa.float32(), 'int64': pa.int64()}[feature['dtype']]
        shape = feature['shape']
        fields.append(pa.field(name, scalar if list(shape) == [1]
                               else pa.list_(scalar, shape[0])))
    return pa.schema(fields)


def data_table(schema, columns):
    """Return a table of one episode's rows: columns {name: (n,) or (n, k) array}."""
    pa, _ = pyarrow()
    arrays = []
    for field in schema:
        values = np.asarray(columns[field.name])
        if pa.types.is_fixed_size_list(field.type):
            flat = pa.array(values.astype(np.float32).ravel(), field.type.value_type)
            arrays.append(pa.FixedSizeListArray.from_arrays(flat, field.type.list_size))
        else:
            arrays.append(pa.array(values.ravel(), field.type))
    return pa.Table.from_arrays(arrays, schema=schema)


class DataFile:
    """One data file written an episode at a time (append), closed by close()."""

    def __init__(self, path, schema):
        _, pq = pyarrow()
        os.makedirs(os.path.dirname(path), exist_ok=True)
        self.path, self.bytes = path, 0
        self._writer = pq.ParquetWriter(path, schema, compression=COMPRESSION,
                                        use_dictionary=True)

    def append(self, table):
        self._writer.write_table(table)
        self.bytes += table.nbytes

    def close(self):
        self._writer.close()


def write_episodes(path, rows):
    """Write meta/episodes rows (lerobot_meta.episode_row dicts) as one Parquet file."""
    pa, pq = pyarrow()
    columns = {key: [row[key] for row in rows] for key in rows[0]}
    os.makedirs(os.path.dirname(path), exist_ok=True)
    pq.write_table(pa.Table.from_pydict(columns), path, compression=COMPRESSION)


def read_episodes(root):
    """Return every row of a dataset's meta/episodes files (dicts, stats/ columns left out), in
    episode order."""
    _, pq = pyarrow()
    folder = os.path.join(root, 'meta', 'episodes')
    rows = []
    for chunk in sorted(os.listdir(folder)) if os.path.isdir(folder) else []:
        for name in sorted(os.listdir(os.path.join(folder, chunk))):
            if name.endswith('.parquet'):
                table = pq.read_table(os.path.join(folder, chunk, name))
                keep = [c for c in table.column_names if not c.startswith('stats/')]
                rows += table.select(keep).to_pylist()
    return sorted(rows, key=lambda row: row['episode_index'])


def write_tasks(path, tasks):
    """Write meta/tasks.parquet: tasks (texts, in task_index order) as pandas writes LeRobot's
    DataFrame: the column task_index and the index 'task' (named in the pandas metadata, so
    that pandas.read_parquet gives the task as the index)."""
    pa, pq = pyarrow()
    table = pa.table({'task_index': pa.array(range(len(tasks)), pa.int64()),
                      'task': pa.array(list(tasks), pa.string())})
    pandas_meta = {
        'index_columns': ['task'],
        'column_indexes': [{'name': None, 'field_name': None, 'pandas_type': 'unicode',
                            'numpy_type': 'object', 'metadata': {'encoding': 'UTF-8'}}],
        'columns': [{'name': 'task_index', 'field_name': 'task_index', 'pandas_type': 'int64',
                     'numpy_type': 'int64', 'metadata': None},
                    {'name': 'task', 'field_name': 'task', 'pandas_type': 'unicode',
                     'numpy_type': 'object', 'metadata': None}],
        'creator': {'library': 'pyarrow', 'version': pa.__version__},
        'pandas_version': '2.0.0'}
    table = table.replace_schema_metadata({'pandas': json.dumps(pandas_meta)})
    os.makedirs(os.path.dirname(path), exist_ok=True)
    pq.write_table(table, path, compression=COMPRESSION)


def read_tasks(path):
    """Return the tasks of a meta/tasks.parquet in task_index order ([] when missing)."""
    if not os.path.exists(path):
        return []
    _, pq = pyarrow()
    table = pq.read_table(path).to_pydict()
    return [task for _, task in sorted(zip(table['task_index'], table['task']))]


def task_index(tasks, task):
    """Return a task's index, appending it to tasks when new."""
    if task not in tasks:
        tasks.append(task)
    return tasks.index(task)


def read_json(path):
    with open(path) as stream:
        return json.load(stream)


def write_json(path, data):
    """Write a JSON file (indent 4, as LeRobot's), whole or not at all (atomic_file)."""
    atomic_file.write_atomic(path, json.dumps(data, indent=4))


def last_files(rows, video_keys):
    """Return where a run appending to a dataset writes: {'data', 'meta', <video key>: (chunk,
    file)} after the last episode's files, or (0, 0) for a new dataset, as LeRobot resumes."""
    if not rows:
        return {key: (0, 0) for key in ['data', 'meta'] + list(video_keys)}
    last = rows[-1]
    out = {'data': lerobot_meta.next_file(last['data/chunk_index'], last['data/file_index']),
           'meta': lerobot_meta.next_file(last['meta/episodes/chunk_index'],
                                          last['meta/episodes/file_index'])}
    for key in video_keys:
        out[key] = lerobot_meta.next_file(last['videos/%s/chunk_index' % key],
                                          last['videos/%s/file_index' % key])
    return out
