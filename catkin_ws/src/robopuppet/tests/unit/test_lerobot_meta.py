"""LeRobot's tables: statistics against numpy on the same numbers (vectors, images, episodes
aggregated), the sampling of frames, chunk and file indices, info.json's keys, the features."""
import numpy as np
import pytest

from robopuppet.episodes import lerobot_meta
from robopuppet.episodes.export import COLUMNS


def test_vector_stats_are_numpys_over_the_frames():
    rng = np.random.default_rng(1)
    values = rng.normal(size=(57, 3))
    stats = lerobot_meta.vector_stats(values)
    assert stats['min'] == pytest.approx(values.min(0))
    assert stats['max'] == pytest.approx(values.max(0))
    assert stats['mean'] == pytest.approx(values.mean(0))
    assert stats['std'] == pytest.approx(values.std(0))
    assert stats['count'].tolist() == [57]
    for key, q in zip(lerobot_meta.QUANTILE_KEYS, lerobot_meta.QUANTILES):
        assert stats[key] == pytest.approx(np.quantile(values, q, axis=0))
    assert lerobot_meta.QUANTILE_KEYS == ('q01', 'q10', 'q50', 'q90', 'q99')
    one = lerobot_meta.vector_stats(np.array([[2.0, 3.0]]))  # one frame: its value, std 0
    assert one['q99'].tolist() == [2.0, 3.0] and one['std'].tolist() == [0.0, 0.0]


def test_image_stats_are_per_channel_over_the_pixels_scaled_to_one():
    rng = np.random.default_rng(2)
    images = [rng.integers(0, 256, size=(24, 32, 3), dtype=np.uint8) for _ in range(5)]
    stats = lerobot_meta.ImageStats()
    for image in images:
        stats.add(image)
    got = stats.stats()
    pixels = np.concatenate([i.reshape(-1, 3) for i in images]).astype(float)
    assert got['mean'].shape == (3, 1, 1) and got['count'].tolist() == [5]
    assert got['mean'].ravel() == pytest.approx(pixels.mean(0) / 255)
    assert got['std'].ravel() == pytest.approx(pixels.std(0) / 255)
    assert got['min'].ravel() == pytest.approx(pixels.min(0) / 255)
    for key, q in zip(lerobot_meta.QUANTILE_KEYS, lerobot_meta.QUANTILES):
        assert got[key].ravel() == pytest.approx(np.quantile(pixels, q, axis=0) / 255), key


def test_large_images_are_seen_every_kth_pixel_as_lerobots_statistics_see_them():
    image = np.arange(480 * 640 * 3, dtype=np.uint32).reshape(480, 640, 3).astype(np.uint8)
    view = lerobot_meta.stats_view(image)
    assert view.shape == (120, 160, 3)  # k = int(640 / 150) = 4
    assert np.array_equal(view, image[::4, ::4])
    small = np.zeros((240, 299, 3), np.uint8)
    assert lerobot_meta.stats_view(small) is small


def test_frames_sampled_for_image_statistics():
    assert lerobot_meta.sample_indices(21) == list(range(21))
    assert len(lerobot_meta.sample_indices(300)) == 100  # 300 ** 0.75 = 72: at least 100
    assert len(lerobot_meta.sample_indices(500)) == 105
    assert len(lerobot_meta.sample_indices(1000)) == 177  # 1000 ** 0.75
    many = lerobot_meta.sample_indices(20000)
    assert len(many) == 1681 and many[0] == 0 and many[-1] == 19999


def test_episode_stats_aggregate_to_the_stats_of_all_frames():
    rng = np.random.default_rng(3)
    parts = [rng.normal(loc=k, size=(n, 4)) for k, n in ((0, 30), (2, 11), (-1, 50))]
    merged = lerobot_meta.aggregate([lerobot_meta.vector_stats(p) for p in parts])
    whole = np.concatenate(parts)
    assert merged['mean'] == pytest.approx(whole.mean(0))
    assert merged['std'] == pytest.approx(whole.std(0))
    assert merged['min'] == pytest.approx(whole.min(0))
    assert merged['max'] == pytest.approx(whole.max(0))
    assert merged['count'].tolist() == [91]
    # quantiles cannot be merged: LeRobot keeps the envelope (lower: least, upper: greatest)
    assert merged['q10'] == pytest.approx(np.min([np.quantile(p, 0.1, axis=0) for p in parts],
                                                 axis=0))
    assert merged['q90'] == pytest.approx(np.max([np.quantile(p, 0.9, axis=0) for p in parts],
                                                 axis=0))
    assert merged['q50'] == pytest.approx(np.min([np.median(p, axis=0) for p in parts], axis=0))


def test_chunks_hold_a_thousand_files():
    assert lerobot_meta.next_file(0, 0) == (0, 1)
    assert lerobot_meta.next_file(0, 999) == (1, 0)
    assert lerobot_meta.DATA_PATH.format(chunk_index=1, file_index=2) == \
        'data/chunk-001/file-002.parquet'
    assert lerobot_meta.VIDEO_PATH.format(video_key='observation.images.room_camera',
                                          chunk_index=0, file_index=0) == \
        'videos/observation.images.room_camera/chunk-000/file-000.mp4'


def test_features_and_info_have_lerobots_names_and_keys():
    video = {'codec': 'h264', 'pix_fmt': 'yuv420p', 'g': 2, 'crf': 23, 'preset': 'veryfast'}
    table = lerobot_meta.features(30, {'room_camera': (640, 480)}, puppet=True, video=video)
    assert list(table) == ['observation.state', 'action', 'observation.velocity',
                           'observation.effort', 'observation.puppet_state',
                           'observation.images.room_camera', 'timestamp', 'frame_index',
                           'episode_index', 'index', 'task_index']
    assert table['observation.state'] == {'dtype': 'float32', 'shape': [16], 'names': COLUMNS}
    room = table['observation.images.room_camera']
    assert room['shape'] == [480, 640, 3] and room['names'] == ['height', 'width', 'channels']
    assert room['info']['video.fps'] == 30 and room['info']['video.codec'] == 'h264'
    info = lerobot_meta.info(30, table, 3, 900, 2)
    assert list(info) == ['codebase_version', 'fps', 'features', 'total_episodes',
                          'total_frames', 'total_tasks', 'chunks_size', 'data_files_size_in_mb',
                          'video_files_size_in_mb', 'data_path', 'video_path', 'robot_type',
                          'splits']
    assert info['splits'] == {'train': '0:3'} and info['chunks_size'] == 1000
    assert (info['data_files_size_in_mb'], info['video_files_size_in_mb']) == (100, 200)
    without = lerobot_meta.features(30, {}, video=video)
    assert lerobot_meta.info(30, without, 1, 1, 1)['video_path'] is None
    assert lerobot_meta.same_features(table, dict(table)) == ''
    assert 'observation.puppet_state' in lerobot_meta.same_features(table, without)


def test_an_episode_row_says_where_its_frames_are():
    stats = {'action': lerobot_meta.vector_stats(np.ones((3, 2)))}
    row = lerobot_meta.episode_row(4, 'grip', 3, (0, 1), 100, (0, 1),
                                   {'observation.images.room_camera': (0, 1, 2.5, 2.6)}, stats)
    assert row['tasks'] == ['grip'] and row['length'] == 3
    assert (row['dataset_from_index'], row['dataset_to_index']) == (100, 103)
    assert row['videos/observation.images.room_camera/from_timestamp'] == 2.5
    assert row['stats/action/count'] == [3] and row['stats/action/q50'] == [1.0, 1.0]
    assert (row['meta/episodes/chunk_index'], row['meta/episodes/file_index']) == (0, 1)
