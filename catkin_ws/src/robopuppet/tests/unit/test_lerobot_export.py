"""export --format lerobot on synthetic episodes with three cameras, read back with the Parquet
reader (pyarrow) and a video decoder (OpenCV's, Debian's libavcodec): every feature against the
bag (values at each frame, frame counts, timestamps, each decoded image against the recorded
JPEG), the statistics against the data, tasks, appending, and what a failure leaves.
"""
import errno
import hashlib
import json
import os
import subprocess
import sys

import cv2
import genpy
import numpy as np
import pytest
import rosbag
import yaml
from sensor_msgs.msg import CompressedImage

from robopuppet.cameras import jpeg
from robopuppet.episodes import (export, export_cli, export_files, lerobot_episode,
                                 lerobot_export, lerobot_meta, lerobot_parquet)
from test_export_files import T0_S, run, write_episode
from test_lerobot_video import frame_times

pa, pq = lerobot_parquet.pyarrow()
CAMERAS = ['left_hand_camera', 'right_hand_camera', 'room_camera']
FPS = 10
WIDTH, HEIGHT = 64, 48
CAMERA_RATE_HZ = 15.0
PSNR_DB = 30.0  # h264 at crf 23 in yuv420p, against the recorded JPEG (quality 90)


def texture(camera, k):
    """Return frame k of a camera (BGR): a smooth pattern that moves with k and differs by
    camera, so that a wrong frame or camera is far off."""
    y, x = np.mgrid[0:HEIGHT, 0:WIDTH]
    c = CAMERAS.index(camera)
    phase = 0.6 * k + 2.0 * c
    image = np.stack([128 + 100 * np.sin(x / 7.0 + phase), 128 + 100 * np.cos(y / 5.0 + phase),
                      np.full(x.shape, 40.0 + 60 * c + 3 * k)], axis=-1)
    return np.clip(image, 0, 255).astype(np.uint8)


def add_cameras(bag_path, duration_s, cameras=CAMERAS, start_s=0.0):
    """Append each camera's frames at 15 frames/s from start_s; return {camera: [(t, JPEG)]}."""
    frames = {camera: [] for camera in cameras}
    with rosbag.Bag(str(bag_path), 'a') as bag:
        for k in range(int(duration_s * CAMERA_RATE_HZ) + 1):
            t_s = start_s + k / CAMERA_RATE_HZ
            for camera in cameras:
                data = jpeg.encode(texture(camera, k), 90)
                frames[camera].append((t_s, data))
                bag.write('/cameras/%s/image/compressed' % camera, CompressedImage(
                    format=jpeg.JPEG_FORMAT, data=data),
                    genpy.Time(T0_S) + genpy.Duration.from_sec(t_s))
    return frames


def episode(directory, name, steps, task=None, notes=''):
    """Write an episode of steps x 0.1 s with three cameras and a task; return (bag, frames)."""
    bag_path = write_episode(directory, name=name, steps=steps)
    frames = add_cameras(bag_path, 0.1 * (steps - 1))
    yaml_path = bag_path.with_suffix('.yaml')
    metadata = yaml.safe_load(yaml_path.read_text())
    metadata.update({'cameras': CAMERAS, 'notes': notes})
    if task is not None:
        metadata['task'] = task
    yaml_path.write_text(yaml.safe_dump(metadata))
    return bag_path, frames


def held_image(frames, t_s):
    """Return the RGB image a grid time shows: the newest frame at or before it (the first
    before the first)."""
    index = max([i for i, (t, _) in enumerate(frames) if t <= t_s + 1e-9] or [0])
    return cv2.cvtColor(cv2.imdecode(np.frombuffer(frames[index][1], np.uint8),
                                     cv2.IMREAD_COLOR), cv2.COLOR_BGR2RGB)


def psnr(image, reference):
    """Return the peak signal-to-noise ratio of an image against its reference (dB)."""
    return 10 * np.log10(255.0 ** 2 / np.mean((image - reference) ** 2))


def decode(path):
    """Return every frame of a video (RGB), decoded in order."""
    capture = cv2.VideoCapture(str(path))
    images = []
    while True:
        ok, image = capture.read()
        if not ok:
            break
        images.append(cv2.cvtColor(image, cv2.COLOR_BGR2RGB))
    capture.release()
    return images


def read_dataset(root):
    info = json.loads((root / 'meta' / 'info.json').read_text())
    data = pq.read_table(str(root / 'data' / 'chunk-000' / 'file-000.parquet'))
    episodes = pq.read_table(str(root / 'meta' / 'episodes' / 'chunk-000' /
                                 'file-000.parquet')).to_pylist()
    stats = json.loads((root / 'meta' / 'stats.json').read_text())
    return info, data, episodes, stats


def expected_rows(bag_path):
    recording = export.collect(export_files.read_messages(str(bag_path),
                                                          export.episode_topics()))
    return export.aloha_arrays(recording, FPS)


def test_the_dataset_reads_back_feature_by_feature_against_the_bags(tmp_path):
    first, first_frames = episode(tmp_path, 'episode_20240102-030405', 21, task='reach and grip')
    second, second_frames = episode(tmp_path, 'episode_20240102-030500', 16, notes='demo 2')
    out = tmp_path / 'dataset'
    assert run([str(first), str(second), '--format', 'lerobot', '--out', str(out),
                '--fps', str(FPS)]) == 0
    info, data, episodes, stats = read_dataset(out)
    assert info['codebase_version'] == 'v3.0' and info['fps'] == FPS
    assert (info['total_episodes'], info['total_frames'], info['total_tasks']) == (2, 37, 2)
    assert info['splits'] == {'train': '0:2'} and info['robot_type'] == 'baxter'
    assert info['features']['observation.state']['names'] == export.COLUMNS
    for camera in CAMERAS:
        feature = info['features']['observation.images.' + camera]
        assert feature['dtype'] == 'video' and feature['shape'] == [HEIGHT, WIDTH, 3]
        assert feature['info']['video.codec'] == 'h264'
        assert feature['info']['video.pix_fmt'] == 'yuv420p'
    tasks = pq.read_table(str(out / 'meta' / 'tasks.parquet')).to_pydict()
    assert dict(zip(tasks['task'], tasks['task_index'])) == {'reach and grip': 0, 'demo 2': 1}
    columns = data.to_pydict()
    assert len(columns['index']) == 37 and columns['index'] == list(range(37))
    videos = {camera: decode(out / 'videos' / ('observation.images.' + camera) / 'chunk-000' /
                             'file-000.mp4') for camera in CAMERAS}
    assert all(len(images) == 37 for images in videos.values())  # frame counts
    assert frame_times(out / 'videos' / 'observation.images.room_camera' / 'chunk-000' /
                       'file-000.mp4') == pytest.approx(np.arange(37) / FPS)  # LeRobot seeks
    start = 0
    for e, (bag_path, frames, steps) in enumerate([(first, first_frames, 21),
                                                   (second, second_frames, 16)]):
        row = episodes[e]
        assert (row['episode_index'], row['length']) == (e, steps)
        assert (row['dataset_from_index'], row['dataset_to_index']) == (start, start + steps)
        assert row['tasks'] == [['reach and grip'], ['demo 2']][e]
        rows = slice(start, start + steps)
        assert columns['episode_index'][rows] == [e] * steps
        assert columns['frame_index'][rows] == list(range(steps))
        assert columns['task_index'][rows] == [e] * steps
        assert np.array_equal(np.float32(columns['timestamp'][rows]),
                              np.float32(np.arange(steps) / FPS))
        arrays = expected_rows(bag_path)
        for feature, key in lerobot_episode.ROW_FEATURES:
            got = np.array(columns[feature][rows], np.float32)
            assert np.array_equal(got, arrays[key].astype(np.float32)), feature
        for camera in CAMERAS:
            key = 'videos/observation.images.%s/' % camera
            assert (row[key + 'from_timestamp'], row[key + 'to_timestamp']) == pytest.approx(
                (start / FPS, (start + steps) / FPS))
            first_video_frame = round(row[key + 'from_timestamp'] * FPS)
            for k in range(steps):
                want = held_image(frames[camera], k / FPS).astype(float)
                image = videos[camera][first_video_frame + k].astype(float)
                assert psnr(image, want) > PSNR_DB, (camera, e, k)
                if k + 3 < steps:  # and not the frame of another time
                    other = held_image(frames[camera], (k + 3) / FPS).astype(float)
                    assert psnr(image, other) < PSNR_DB - 10
        start += steps
    check_stats(stats, columns, episodes, first_frames, second_frames)


def check_stats(stats, columns, episodes, first_frames, second_frames):
    """stats.json against the data: min, max, mean, std and count of every row feature over
    all frames, each episode's quantiles numpy's, the dataset's LeRobot's envelope of them;
    the cameras' per channel over the held images, scaled to 0..1."""
    lengths = [row['length'] for row in episodes]
    for feature in ('observation.state', 'action', 'observation.velocity',
                    'observation.effort', 'timestamp', 'frame_index', 'index'):
        values = np.array(columns[feature], np.float64).reshape(sum(lengths), -1)
        got = {key: np.array(value) for key, value in stats[feature].items()}
        assert got['count'].tolist() == [sum(lengths)]
        for key, want in (('min', values.min(0)), ('max', values.max(0)),
                          ('mean', values.mean(0)), ('std', values.std(0))):
            assert got[key].ravel() == pytest.approx(want, abs=1e-6), (feature, key)
        parts = [values[:lengths[0]], values[lengths[0]:]]
        for e, part in enumerate(parts):
            assert np.ravel(episodes[e]['stats/%s/q10' % feature]) == pytest.approx(
                np.quantile(part, 0.10, axis=0), abs=1e-6)
        assert got['q01'].ravel() == pytest.approx(
            np.minimum(*[np.quantile(p, 0.01, axis=0) for p in parts]), abs=1e-6)
        assert got['q99'].ravel() == pytest.approx(
            np.maximum(*[np.quantile(p, 0.99, axis=0) for p in parts]), abs=1e-6)
    for camera in CAMERAS:
        pixels = np.concatenate([
            np.stack([held_image(frames[camera], k / FPS) for k in range(length)]).reshape(-1, 3)
            for frames, length in ((first_frames, lengths[0]), (second_frames, lengths[1]))])
        got = stats['observation.images.' + camera]
        assert np.array(got['mean']).shape == (3, 1, 1)
        assert np.ravel(got['mean']) == pytest.approx(pixels.mean(0) / 255.0, abs=1e-9)
        assert np.ravel(got['std']) == pytest.approx(pixels.std(0) / 255.0, abs=1e-9)
        assert np.ravel(got['max']) == pytest.approx(pixels.max(0) / 255.0)
        assert got['count'] == [sum(lengths)]  # every frame sampled (fewer than 100)


def digest(root):
    """Return {relative path: sha256} of every file under root."""
    return {os.path.relpath(os.path.join(folder, name), root):
            hashlib.sha256(open(os.path.join(folder, name), 'rb').read()).hexdigest()
            for folder, _, names in os.walk(root) for name in names}


def test_appending_adds_files_and_leaves_the_old_ones_as_they_were(tmp_path, capsys):
    first, _ = episode(tmp_path, 'episode_20240102-030405', 11, task='reach and grip')
    second, second_frames = episode(tmp_path, 'episode_20240102-030500', 11, task='put down')
    out = tmp_path / 'dataset'
    argv = ['--format', 'lerobot', '--out', str(out), '--fps', str(FPS)]
    assert run([str(first)] + argv) == 0
    before = digest(out)
    assert run([str(second)] + argv) == 0
    after = digest(out)
    changed = {path for path in before if after[path] != before[path]}
    assert changed == {'meta/info.json', 'meta/stats.json', 'meta/tasks.parquet',
                       'meta/robopuppet_episodes.json'}
    assert set(after) - set(before) == {
        'data/chunk-000/file-001.parquet', 'meta/episodes/chunk-000/file-001.parquet'} | {
        'videos/observation.images.%s/chunk-000/file-001.mp4' % c for c in CAMERAS}
    info = json.loads((out / 'meta' / 'info.json').read_text())
    assert (info['total_episodes'], info['total_frames'], info['total_tasks']) == (2, 22, 2)
    assert lerobot_parquet.read_tasks(str(out / 'meta' / 'tasks.parquet')) == [
        'reach and grip', 'put down']
    data = pq.read_table(str(out / 'data' / 'chunk-000' / 'file-001.parquet')).to_pydict()
    assert data['index'] == list(range(11, 22)) and data['episode_index'] == [1] * 11
    assert data['task_index'] == [1] * 11
    row = pq.read_table(str(out / 'meta' / 'episodes' / 'chunk-000' /
                            'file-001.parquet')).to_pylist()[0]
    assert row['dataset_from_index'] == 11 and row['data/file_index'] == 1
    assert row['videos/observation.images.room_camera/from_timestamp'] == 0.0
    video = decode(out / 'videos' / 'observation.images.room_camera' / 'chunk-000' /
                   'file-001.mp4')
    assert len(video) == 11
    assert psnr(video[4].astype(float),
                held_image(second_frames['room_camera'], 0.4).astype(float)) > PSNR_DB
    assert 'appending to' in capsys.readouterr().out
    assert run([str(second), str(first)] + argv) == 0  # in already: nothing to do
    assert 'in the dataset already, as episode 0: skipped' in capsys.readouterr().out
    assert digest(out) == after
    assert json.loads((out / 'meta' / 'robopuppet_episodes.json').read_text()) == {
        '0': first.stem, '1': second.stem}
    assert not [p for p in os.listdir(tmp_path) if p.endswith('.part')]


def test_a_bad_episode_or_a_missing_camera_is_left_out_with_an_error(tmp_path, capsys):
    good, _ = episode(tmp_path, 'episode_20240102-030405', 11)
    (tmp_path / 'episode_20240102-030600.bag').write_bytes(b'not a bag')
    no_room = write_episode(tmp_path, name='episode_20240102-030700')
    add_cameras(no_room, 1.0, cameras=CAMERAS[:2])
    out = tmp_path / 'dataset'
    assert run([str(good), str(tmp_path / 'episode_20240102-030600.bag'), str(no_room),
                '--format', 'lerobot', '--out', str(out), '--fps', str(FPS)]) == 1
    err = capsys.readouterr().err
    assert 'cannot read the bag' in err and 'no frames of room_camera' in err
    assert '2 of 3 episodes failed (left out of the dataset)' in err
    info = json.loads((out / 'meta' / 'info.json').read_text())
    assert (info['total_episodes'], info['total_frames']) == (1, 11)
    assert json.loads((out / 'meta' / 'stats.json').read_text())['index']['max'] == [10]


@pytest.mark.parametrize('failure', ['disk full', 'interrupted'])
def test_a_failed_append_leaves_the_dataset_as_it_was(tmp_path, monkeypatch, capsys, failure):
    first, _ = episode(tmp_path, 'episode_20240102-030405', 11)
    second, _ = episode(tmp_path, 'episode_20240102-030500', 11)
    out = tmp_path / 'dataset'
    argv = ['--format', 'lerobot', '--out', str(out), '--fps', str(FPS)]
    assert run([str(first)] + argv) == 0
    before = digest(out)
    if failure == 'disk full':
        def full(*_):
            raise OSError(errno.ENOSPC, 'No space left on device')
        monkeypatch.setattr(lerobot_parquet, 'write_json', full)  # the last files written
        assert run([str(second)] + argv) == 1
        assert 'No space left on device' in capsys.readouterr().err
    else:
        def interrupted(*_):
            raise KeyboardInterrupt
        monkeypatch.setattr(lerobot_episode.export_images.ImageResampler, 'finish',
                            interrupted)  # while the videos are written
        with pytest.raises(KeyboardInterrupt):
            export_cli.main([str(second)] + argv)
    assert digest(out) == before
    assert sorted(os.listdir(tmp_path)) == sorted(p for p in os.listdir(tmp_path)
                                                  if not p.endswith('.part'))


def test_a_killed_runs_work_folder_is_removed_and_a_non_dataset_refused(tmp_path, capsys):
    good, _ = episode(tmp_path, 'episode_20240102-030405', 11)
    dead = subprocess.Popen(['true'])
    dead.wait()
    stale = tmp_path / ('.dataset.lerobot.%d.part' % dead.pid)
    (stale / 'meta').mkdir(parents=True)
    out = tmp_path / 'dataset'
    assert run([str(good), '--format', 'lerobot', '--out', str(out), '--fps', '10']) == 0
    assert not stale.exists()
    other = tmp_path / 'photos'
    other.mkdir()
    (other / 'a.jpg').write_bytes(b'x')
    assert run([str(good), '--format', 'lerobot', '--out', str(other)]) == 1
    assert 'neither empty nor a LeRobot dataset' in capsys.readouterr().err
    assert os.listdir(other) == ['a.jpg']
    assert run([str(good), '--format', 'lerobot', '--out', str(out), '--fps', '20']) == 1
    assert 'give --fps 10' in capsys.readouterr().err
    before = digest(out)
    smaller, _ = episode(tmp_path, 'episode_20240102-030500', 11)
    assert run([str(smaller), '--format', 'lerobot', '--out', str(out), '--fps', '10',
                '--image-size', '32x24']) == 1
    assert ('it does not fit the dataset: its features differ in observation.images.'
            'left_hand_camera') in capsys.readouterr().err
    assert digest(out) == before


def test_progress_lines_and_the_puppets_angles(tmp_path, capsys, monkeypatch):
    good, _ = episode(tmp_path, 'episode_20240102-030405', 11)
    monkeypatch.setattr(export_cli, 'PROGRESS_PERIOD_S', 0.0)
    out = tmp_path / 'dataset'
    assert run([str(good), '--format', 'lerobot', '--out', str(out), '--fps', str(FPS),
                '--puppet', '--no-images']) == 0
    out_text = capsys.readouterr().out
    assert 'lerobot: [' in out_text and '%: episode 1 of 1' in out_text
    info, data, _, _ = read_dataset(out)
    assert not any(f['dtype'] == 'video' for f in info['features'].values())
    assert info['video_path'] is None
    puppet = np.array(data.to_pydict()['observation.puppet_state'])
    # puppet R's joint j at 0.01 j + 0.1 k rad (write_episode), puppet L never recorded: 0
    assert puppet[:, :7].tolist() == [[0.0] * 7] * 11
    assert puppet[5, 7:] == pytest.approx([0.01 * j + 0.5 for j in range(7)], abs=1e-6)
    out2 = tmp_path / 'dataset2'
    assert run([str(good), '--format', 'lerobot', '--out', str(out2), '--fps', str(FPS)]) == 0
    assert 'lerobot: [####################] 100 %' in capsys.readouterr().out


def test_without_pyarrow_the_error_names_the_set_up(tmp_path):
    code = ('import sys; sys.modules["pyarrow"] = None\n'
            'from robopuppet.episodes import export_cli\nexport_cli.main(sys.argv[1:])')
    result = subprocess.run([sys.executable, '-c', code, 'e', '--format', 'lerobot', '--out',
                             str(tmp_path / 'd')], capture_output=True, text=True, check=False)
    assert result.returncode == 1
    assert 'needs pyarrow' in result.stderr and 'tools/setup.sh' in result.stderr


def test_the_options_of_the_lerobot_format(capsys):
    for argv in (['e', '--format', 'lerobot'], ['e', '--format', 'lerobot', '--format', 'csv',
                                                '--out', 'd'],
                 ['e', '--format', 'lerobot', '--out', 'd', '--fps', '0'],
                 ['e', '--format', 'lerobot', '--out', 'd', '--plot']):
        with pytest.raises(SystemExit):
            export_cli.parse_args(argv)
    args = export_cli.parse_args(['e', '--format', 'lerobot', '--out', 'd'])
    assert (args.fps, args.image_size, args.video_codec) == (30, None, 'h264')
    capsys.readouterr()


@pytest.mark.parametrize('code', [errno.EINVAL, errno.ENOSYS])
def test_without_an_atomic_exchange_the_swap_falls_back_to_two_renames(tmp_path, monkeypatch,
                                                                        code):
    class NoExchange:   # a file system (NFS, ...) without renameat2's RENAME_EXCHANGE
        @staticmethod
        def renameat2(*_args):
            return -1
    monkeypatch.setattr(lerobot_export.ctypes, 'CDLL', lambda *a, **k: NoExchange())
    monkeypatch.setattr(lerobot_export.ctypes, 'get_errno', lambda: code)
    out, work = tmp_path / 'dataset', tmp_path / '.dataset.lerobot.1.part'
    out.mkdir()
    (out / 'old').write_text('old')
    work.mkdir()
    (work / 'new').write_text('new')
    lerobot_export._swap(str(work), str(out))
    assert sorted(os.listdir(out)) == ['new'] and sorted(os.listdir(tmp_path)) == ['dataset']


def test_another_failure_of_the_swap_leaves_the_dataset_as_it_was(tmp_path, monkeypatch):
    class Failing:
        @staticmethod
        def renameat2(*_args):
            return -1
    monkeypatch.setattr(lerobot_export.ctypes, 'CDLL', lambda *a, **k: Failing())
    monkeypatch.setattr(lerobot_export.ctypes, 'get_errno', lambda: errno.EIO)
    out, work = tmp_path / 'dataset', tmp_path / '.dataset.lerobot.1.part'
    out.mkdir()
    (out / 'old').write_text('old')
    work.mkdir()
    with pytest.raises(OSError):
        lerobot_export._swap(str(work), str(out))
    assert sorted(os.listdir(out)) == ['old']
