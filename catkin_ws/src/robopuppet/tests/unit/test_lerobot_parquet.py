"""The dataset's Parquet files read back with pyarrow: the rows' schema (vectors as fixed-size
lists), tasks in the layout pandas gives LeRobot, the episodes' rows, where an append writes."""
import json

import numpy as np

from robopuppet.episodes import lerobot_meta, lerobot_parquet

pa, pq = lerobot_parquet.pyarrow()


def test_rows_are_written_with_fixed_size_lists_and_scalars(tmp_path):
    features = lerobot_meta.features(10, {}, video={})
    schema = lerobot_parquet.data_schema(features)
    assert schema.field('observation.state').type == pa.list_(pa.float32(), 16)
    assert schema.field('timestamp').type == pa.float32()
    assert schema.field('index').type == pa.int64()
    columns = {name: np.arange(3) for name, _ in lerobot_meta.INDEX_FEATURES}
    for name in ('observation.state', 'action', 'observation.velocity', 'observation.effort'):
        columns[name] = np.arange(48, dtype=np.float32).reshape(3, 16)
    path = str(tmp_path / 'data' / 'chunk-000' / 'file-000.parquet')
    data = lerobot_parquet.DataFile(path, schema)
    data.append(lerobot_parquet.data_table(schema, columns))
    data.append(lerobot_parquet.data_table(schema, columns))
    data.close()
    table = pq.read_table(path).to_pydict()
    assert table['index'] == [0, 1, 2, 0, 1, 2]
    assert table['action'][1] == list(range(16, 32))


def test_tasks_are_indexed_by_their_text_as_pandas_reads_them(tmp_path):
    path = str(tmp_path / 'meta' / 'tasks.parquet')
    tasks = ['reach and grip']
    assert lerobot_parquet.task_index(tasks, 'put down') == 1
    assert lerobot_parquet.task_index(tasks, 'reach and grip') == 0
    lerobot_parquet.write_tasks(path, tasks)
    assert lerobot_parquet.read_tasks(path) == ['reach and grip', 'put down']
    table = pq.read_table(path)
    assert table.to_pydict() == {'task_index': [0, 1], 'task': ['reach and grip', 'put down']}
    assert json.loads(table.schema.metadata[b'pandas'])['index_columns'] == ['task']
    assert lerobot_parquet.read_tasks(str(tmp_path / 'none.parquet')) == []


def test_an_append_writes_after_the_last_episodes_files(tmp_path):
    key = 'observation.images.room_camera'
    assert lerobot_parquet.last_files([], [key]) == {'data': (0, 0), 'meta': (0, 0),
                                                     key: (0, 0)}
    stats = {'action': lerobot_meta.vector_stats(np.zeros((2, 2)))}
    rows = [lerobot_meta.episode_row(e, 't', 2, (0, e), 2 * e, (0, e), {key: (0, e, 0.0, 0.2)},
                                     stats) for e in range(2)]
    for e, row in enumerate(rows):
        lerobot_parquet.write_episodes(str(tmp_path / 'meta' / 'episodes' / 'chunk-000' /
                                           ('file-%03d.parquet' % e)), [row])
    read = lerobot_parquet.read_episodes(str(tmp_path))
    assert [r['episode_index'] for r in read] == [0, 1]
    assert not [c for c in read[0] if c.startswith('stats/')]
    assert lerobot_parquet.last_files(read, [key]) == {'data': (0, 2), 'meta': (0, 2),
                                                       key: (0, 2)}
