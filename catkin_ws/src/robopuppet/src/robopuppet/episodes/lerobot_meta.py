"""The LeRobotDataset v3.0 format's tables, written by lerobot_export: file layout, features,
info.json, per-episode and dataset statistics, the episodes table's rows.

The format is LeRobot's own (src/lerobot/datasets/utils.py, dataset_metadata.py,
compute_stats.py, dataset_writer.py of the commit named in docs/demonstrations.md): the names,
keys and numbers here are its facts; the code is ours. Pure (numpy; no ROS, no Parquet).
"""
import numpy as np

from robopuppet.episodes.export import COLUMNS

CODEBASE_VERSION = 'v3.0'
ROBOT_TYPE = 'baxter'
CHUNKS_SIZE = 1000             # files per chunk-NNN folder
DATA_FILES_SIZE_IN_MB = 100    # a data file's size before the next one starts
VIDEO_FILES_SIZE_IN_MB = 200   # a video file's
INFO_PATH, STATS_PATH, TASKS_PATH = 'meta/info.json', 'meta/stats.json', 'meta/tasks.parquet'
CHUNK_FILE = 'chunk-{chunk_index:03d}/file-{file_index:03d}'
EPISODES_PATH = 'meta/episodes/' + CHUNK_FILE + '.parquet'
DATA_PATH = 'data/' + CHUNK_FILE + '.parquet'
VIDEO_PATH = 'videos/{video_key}/' + CHUNK_FILE + '.mp4'
QUANTILES = (0.01, 0.10, 0.50, 0.90, 0.99)
QUANTILE_KEYS = tuple('q%02d' % round(q * 100) for q in QUANTILES)
STAT_KEYS = ('min', 'max', 'mean', 'std', 'count') + QUANTILE_KEYS
STATE, ACTION, VELOCITY, EFFORT = 'observation.state', 'action', 'observation.velocity', \
    'observation.effort'
PUPPET = 'observation.puppet_state'
PUPPET_NAMES = ['puppet_%s_joint_%d' % (side, j) for side in 'LR' for j in range(7)]
IMAGE_PREFIX = 'observation.images.'
INDEX_FEATURES = (('timestamp', 'float32'), ('frame_index', 'int64'),
                  ('episode_index', 'int64'), ('index', 'int64'), ('task_index', 'int64'))
DEFAULT_TASK = 'teleoperated demonstration'


def next_file(chunk_index, file_index):
    """Return the (chunk, file) indices after these: CHUNKS_SIZE files a chunk."""
    if file_index == CHUNKS_SIZE - 1:
        return chunk_index + 1, 0
    return chunk_index, file_index + 1


def video_key(camera):
    """Return a camera's feature name, e.g. observation.images.room_camera."""
    return IMAGE_PREFIX + camera


def features(fps, cameras, puppet=False, video=None):
    """Return the features table: the rows' vectors (float32, with names), the cameras' videos
    ({camera: (W, H)}) and the five index columns, in LeRobot's order (its defaults last).
    video: {'codec', 'pix_fmt', 'g', 'crf', 'preset'} of the encoder."""
    table = {}
    vectors = [(STATE, COLUMNS), (ACTION, COLUMNS), (VELOCITY, COLUMNS), (EFFORT, COLUMNS)]
    if puppet:
        vectors.append((PUPPET, PUPPET_NAMES))
    for name, names in vectors:
        table[name] = {'dtype': 'float32', 'shape': [len(names)], 'names': list(names)}
    for camera, (width, height) in sorted(cameras.items()):
        info = {'video.height': height, 'video.width': width, 'video.codec': video['codec'],
                'video.pix_fmt': video['pix_fmt'], 'video.fps': int(fps), 'video.channels': 3,
                'video.g': video['g'], 'video.crf': video['crf'],
                'video.preset': video['preset'], 'video.fast_decode': 0,
                'video.extra_options': {}, 'has_audio': False, 'is_depth_map': False}
        table[video_key(camera)] = {'dtype': 'video', 'shape': [height, width, 3],
                                    'names': ['height', 'width', 'channels'], 'info': info}
    for name, dtype in INDEX_FEATURES:
        table[name] = {'dtype': dtype, 'shape': [1], 'names': None}
    return table


def info(fps, feature_table, total_episodes, total_frames, total_tasks):
    """Return meta/info.json's dict (the keys of LeRobot's DatasetInfo, in its order)."""
    videos = any(f['dtype'] == 'video' for f in feature_table.values())
    return {'codebase_version': CODEBASE_VERSION, 'fps': int(fps), 'features': feature_table,
            'total_episodes': total_episodes, 'total_frames': total_frames,
            'total_tasks': total_tasks, 'chunks_size': CHUNKS_SIZE,
            'data_files_size_in_mb': DATA_FILES_SIZE_IN_MB,
            'video_files_size_in_mb': VIDEO_FILES_SIZE_IN_MB, 'data_path': DATA_PATH,
            'video_path': VIDEO_PATH if videos else None, 'robot_type': ROBOT_TYPE,
            'splits': {'train': '0:%d' % total_episodes}}


def quantile(sorted_values, q):
    """Return numpy's 'linear' quantile of ascending values."""
    position = q * (len(sorted_values) - 1)
    low = int(np.floor(position))
    high = min(low + 1, len(sorted_values) - 1)
    return sorted_values[low] + (position - low) * (sorted_values[high] - sorted_values[low])


def vector_stats(values):
    """Return the statistics of rows (n, k) or a column (n,), per column: min, max, mean, std
    (population), count [n] and the quantiles (exact; LeRobot's histogram approximates them;
    a single row: its value, as LeRobot's)."""
    array = np.asarray(values, np.float64)
    matrix = array.reshape(len(array), -1)
    ordered = np.sort(matrix, axis=0)
    stats = {'min': ordered[0], 'max': ordered[-1], 'mean': matrix.mean(axis=0),
             'std': matrix.std(axis=0), 'count': np.array([len(matrix)])}
    for key, q in zip(QUANTILE_KEYS, QUANTILES):
        stats[key] = quantile(ordered, q)
    return stats


def sample_indices(frames):
    """Return the frame indices whose images LeRobot's statistics sample: evenly spread,
    100 (all of fewer) up to 10 000, frames ** 0.75 in between."""
    wanted = max(min(100, frames), min(int(frames ** 0.75), 10000))
    return sorted(set(np.round(np.linspace(0, frames - 1, wanted)).astype(int).tolist()))


def stats_view(image):
    """Return an image (H, W, 3) as LeRobot's statistics see it: every k-th pixel both ways,
    k = int(longer side / 150), when its longer side is 300 pixels or more."""
    height, width = image.shape[:2]
    if max(width, height) < 300:
        return image
    step = int(max(width, height) / 150)
    return image[::step, ::step]


class ImageStats:
    """Per-channel statistics of uint8 RGB images, from a 256-bin histogram per channel (exact,
    memory one histogram); values scaled to 0..1 and shaped (3, 1, 1) as LeRobot's."""

    def __init__(self):
        self.histogram = np.zeros((3, 256), np.int64)
        self.images = 0

    def add(self, image):
        view = stats_view(image)
        for c in range(3):
            self.histogram[c] += np.bincount(view[..., c].ravel(), minlength=256)
        self.images += 1

    def stats(self):
        levels = np.arange(256, dtype=np.float64)
        out = {key: np.zeros((3, 1, 1)) for key in STAT_KEYS if key != 'count'}
        for c in range(3):
            counts = self.histogram[c]
            present = np.flatnonzero(counts)
            total = counts.sum()
            mean = (counts * levels).sum() / total
            out['min'][c], out['max'][c] = levels[present[0]], levels[present[-1]]
            out['mean'][c] = mean
            out['std'][c] = np.sqrt(max((counts * (levels - mean) ** 2).sum() / total, 0.0))
            cumulative = np.cumsum(counts)
            for key, q in zip(QUANTILE_KEYS, QUANTILES):
                out[key][c] = _histogram_quantile(cumulative, q)
        stats = {key: value / 255.0 for key, value in out.items()}
        stats['count'] = np.array([self.images])
        return stats


def _histogram_quantile(cumulative, q):
    """Return the 'linear' quantile of the values a cumulative histogram counts."""
    position = q * (cumulative[-1] - 1)
    low = int(np.floor(position))
    value_low = float(np.searchsorted(cumulative, low, side='right'))
    value_high = float(np.searchsorted(cumulative, min(low + 1, cumulative[-1] - 1),
                                       side='right'))
    return value_low + (position - low) * (value_high - value_low)


def aggregate(stats_list):
    """Return the dataset's statistics of one feature from its episodes' (LeRobot's
    aggregate_feature_stats): min of mins, max of maxes, the count-weighted mean, the pooled
    std, the summed count; a lower quantile (q <= 50) the least, a higher the greatest."""
    means = np.stack([np.asarray(s['mean'], float) for s in stats_list])
    counts = np.stack([np.asarray(s['count'], float) for s in stats_list])
    total = counts.sum(axis=0)
    weights = counts.reshape((len(stats_list),) + (1,) * (means.ndim - 1))
    mean = (means * weights).sum(axis=0) / total
    variances = np.stack([np.asarray(s['std'], float) ** 2 for s in stats_list])
    variance = ((variances + (means - mean) ** 2) * weights).sum(axis=0) / total
    out = {'min': np.min(np.stack([s['min'] for s in stats_list]), axis=0),
           'max': np.max(np.stack([s['max'] for s in stats_list]), axis=0),
           'mean': mean, 'std': np.sqrt(variance),
           'count': np.asarray(total, np.int64).reshape(1)}
    for key in QUANTILE_KEYS:
        values = np.stack([np.asarray(s[key], float) for s in stats_list])
        out[key] = values.min(axis=0) if int(key[1:]) <= 50 else values.max(axis=0)
    return out


def aggregate_all(stats_dicts):
    """Return {feature: aggregate(...)} over dicts of {feature: stats}."""
    keys = {key for stats in stats_dicts for key in stats}
    return {key: aggregate([s[key] for s in stats_dicts if key in s]) for key in sorted(keys)}


def to_json(stats):
    """Return {feature: {stat: nested lists}} for stats.json."""
    return {feature: {key: np.asarray(value).tolist() for key, value in values.items()}
            for feature, values in stats.items()}


def from_json(stats):
    """Return stats.json's dict as numpy arrays."""
    return {feature: {key: np.asarray(value) for key, value in values.items()}
            for feature, values in stats.items()}


def episode_row(episode_index, task, length, data_file, from_index, meta_file, videos, stats):
    """Return an episode's row of meta/episodes: indices, its task, where its rows (data_file
    (chunk, file), dataset from/to index) and videos ({key: (chunk, file, from_s, to_s)}) are,
    and its statistics flattened as stats/<feature>/<stat>."""
    row = {'episode_index': episode_index, 'tasks': [task], 'length': length,
           'data/chunk_index': data_file[0], 'data/file_index': data_file[1],
           'dataset_from_index': from_index, 'dataset_to_index': from_index + length}
    for key, (chunk, file_, from_s, to_s) in sorted(videos.items()):
        row.update({'videos/%s/chunk_index' % key: chunk, 'videos/%s/file_index' % key: file_,
                    'videos/%s/from_timestamp' % key: from_s,
                    'videos/%s/to_timestamp' % key: to_s})
    row['meta/episodes/chunk_index'], row['meta/episodes/file_index'] = meta_file
    for feature, values in sorted(stats.items()):
        for key in STAT_KEYS:
            row['stats/%s/%s' % (feature, key)] = np.asarray(values[key]).tolist()
    return row


def same_features(old, new):
    """Return why a dataset's features (info.json) cannot take the new ones, '' when they can:
    the same names, dtypes and shapes (the videos' encoder settings may differ)."""
    def shape(table):
        return {k: (f['dtype'], list(f['shape']), f.get('names')) for k, f in table.items()}
    old_shapes, new_shapes = shape(old), shape(new)
    differ = sorted(k for k in set(old) | set(new) if old_shapes.get(k) != new_shapes.get(k))
    return 'its features differ in %s' % ', '.join(differ) if differ else ''
