"""Camera images in the ALOHA export: frames held onto the time grid (which frame at which
step, RGB order, skipped frames) checked against hand-made solid-colour JPEGs, first on the pure
resampler, then through the export command on a small bag with CompressedImage frames.
"""
import genpy
import h5py
import numpy as np
import pytest
import rosbag
import yaml
from sensor_msgs.msg import CompressedImage

from robopuppet.cameras import jpeg
from robopuppet.episodes import export, export_cli, export_images, export_size
from test_export_files import T0_S, run, write_episode

# BGR, as OpenCV and the camera nodes hold images; the export must give RGB
BGR = {'red': (0, 0, 255), 'green': (0, 255, 0), 'blue': (255, 0, 0), 'white': (255, 255, 255)}
RGB = {'red': (255, 0, 0), 'green': (0, 255, 0), 'blue': (0, 0, 255), 'white': (255, 255, 255)}
GARBAGE = b'\xff\xd8 not a JPEG'
GRID_S = [0.0, 0.25, 0.5, 0.75, 1.0]


def frame(colour, width=16, height=12):
    """Return the JPEG of a solid-colour image."""
    return jpeg.encode(np.full((height, width, 3), BGR[colour], np.uint8), 95)


def held(resampler, frames, camera='cam'):
    """Feed (t, jpeg) frames of one camera; return the image of each grid step (None if the
    resampler left it empty) and the runs' (start, stop)."""
    runs = [r for t, data in frames for r in resampler.add(camera, t, data)]
    runs += resampler.finish()
    steps = [None] * len(GRID_S)
    for r in runs:
        assert r.camera == camera and r.image.dtype == np.uint8
        for k in range(r.start, r.stop):
            steps[k] = r.image
    return steps, [(r.start, r.stop) for r in runs]


def colours(steps):
    """Return the name of each step's solid colour (within JPEG's error)."""
    names = []
    for image in steps:
        mean = image.reshape(-1, 3).mean(axis=0)
        names.append(next(n for n, rgb in RGB.items() if np.abs(mean - rgb).max() < 6))
    return names


def test_frame_topics_name_their_camera():
    assert export_images.frame_topic('room_camera') == '/cameras/room_camera/image/compressed'
    assert export_images.camera_of('/cameras/room_camera/image/compressed') == 'room_camera'
    for other in ('/cameras/room_camera/image', '/cameras/a/b/image/compressed',
                  '/robot/joint_states'):
        assert export_images.camera_of(other) is None


def test_a_pure_red_bgr_frame_comes_out_rgb_red():
    image = export_images.decode(frame('red'))
    assert image.shape == (12, 16, 3) and image.dtype == np.uint8
    assert np.abs(image.astype(int) - (255, 0, 0)).max() <= 3
    assert export_images.decode(GARBAGE) is None


def test_each_step_shows_the_newest_frame_at_or_before_it():
    resampler = export_images.ImageResampler(GRID_S)
    # green is followed by blue before any step: never shown, so never decoded (it is
    # garbage, and no skip is reported); blue lands exactly on the step at 0.5 s; the frame
    # after the last step is never shown
    steps, runs = held(resampler, [(0.1, frame('red')), (0.3, GARBAGE), (0.5, frame('blue')),
                                   (0.9, frame('white')), (1.2, GARBAGE)])
    assert colours(steps) == ['red', 'red', 'blue', 'blue', 'white']
    assert runs == [(0, 2), (2, 4), (4, 5)]  # each frame decoded and written once
    assert resampler.cameras == ['cam']
    assert resampler.report() == [
        'images of cam, 5 steps each',
        'cam: first frame at 0.100 s: the steps before show it']


def test_bad_and_resized_frames_are_skipped_and_reported():
    resampler = export_images.ImageResampler(GRID_S)
    steps, _ = held(resampler, [(-0.5, GARBAGE), (0.1, frame('red')), (0.3, GARBAGE),
                                (0.6, frame('green', width=32)), (0.9, frame('blue'))])
    # step 0 would show the garbage at -0.5 s: it shows the first good frame instead
    assert colours(steps) == ['red', 'red', 'red', 'red', 'blue']
    assert resampler.report()[1:] == [
        'cam: first frame at 0.100 s: the steps before show it',
        'cam: skipped frames that do not decode: 2 (the first at -0.500 s), '
        'frames of 32x12, not 16x12: 1 (the first at 0.600 s); the steps keep the frame before']


def test_cameras_are_held_apart_and_a_camera_without_a_good_frame_fails():
    resampler = export_images.ImageResampler(GRID_S)
    runs = resampler.add('a', 0.0, frame('red')) + resampler.add('b', 0.0, frame('blue'))
    runs += resampler.add('a', 0.6, frame('green')) + resampler.finish()
    assert [(r.camera, r.start, r.stop, colours([r.image])[0]) for r in runs] == [
        ('a', 0, 3, 'red'), ('a', 3, 5, 'green'), ('b', 0, 5, 'blue')]
    broken = export_images.ImageResampler(GRID_S)
    broken.add('room_camera', 0.0, GARBAGE)
    with pytest.raises(export.ExportError, match='room_camera: none of its frames decodes'):
        broken.finish()


def add_frames(bag_path, frames, cameras=None):
    """Append (camera, t s after the first joint state, colour or bytes) frames to an episode
    of write_episode; cameras: the metadata's list (not written when None)."""
    with rosbag.Bag(str(bag_path), 'a') as bag:
        for camera, t_s, content in frames:
            data = frame(content, 32, 24) if content in BGR else content
            stamp = genpy.Time(T0_S) + genpy.Duration.from_sec(t_s)
            bag.write(export_images.frame_topic(camera), CompressedImage(
                format=jpeg.JPEG_FORMAT, data=data), stamp)
    if cameras is not None:
        yaml_path = bag_path.with_suffix('.yaml')
        metadata = yaml.safe_load(yaml_path.read_text())
        metadata['cameras'] = cameras
        yaml_path.write_text(yaml.safe_dump(metadata))


def read_images(path):
    with h5py.File(str(path), 'r') as root:
        images = root['/observations/images']
        assert root['/observations/qpos'].shape[0] == 11
        return {name: (dataset[()], dataset.chunks, dataset.compression)
                for name, dataset in images.items()}


def test_the_hdf5_holds_each_cameras_images_on_the_grid(tmp_path, capsys, monkeypatch):
    bag_path = write_episode(tmp_path)  # joint states every 0.1 s for 1.0 s
    add_frames(bag_path, [('right_hand_camera', 0.0, 'blue'), ('room_camera', 0.05, 'red'),
                          ('room_camera', 0.42, 'green'), ('room_camera', 0.7, GARBAGE)],
               cameras=['room_camera', 'left_hand_camera', 'right_hand_camera'])
    monkeypatch.setattr(export_cli, 'PROGRESS_PERIOD_S', 0.0)
    assert run([str(bag_path), '--rate', '10', '--image-size', 'full']) == 0
    images = read_images(tmp_path / 'episode_20240102-030405.hdf5')
    assert sorted(images) == ['right_hand_camera', 'room_camera']
    room, chunks, compression = images['room_camera']
    assert room.shape == (11, 24, 32, 3) and room.dtype == np.uint8
    assert chunks == (1, 24, 32, 3) and compression == 'lzf'
    # grid 0.0 .. 1.0 s: red (its first frame, 0.05 s) up to 0.4 s, green from 0.5 s on;
    # the garbage at 0.7 s is skipped
    assert colours(room) == ['red'] * 5 + ['green'] * 6
    assert colours(images['right_hand_camera'][0]) == ['blue'] * 11
    out = capsys.readouterr().out
    assert 'the metadata lists left_hand_camera, but the bag has no frames of them' in out
    assert 'images of right_hand_camera, room_camera, 11 steps each' in out
    assert 'room_camera: skipped frames that do not decode: 1 (the first at 0.700 s)' in out
    assert 'images 100 %' in out


def test_cameras_can_be_chosen_or_left_out(tmp_path, capsys):
    bag_path = write_episode(tmp_path)
    add_frames(bag_path, [('right_hand_camera', 0.0, 'blue'), ('room_camera', 0.0, 'red')])
    hdf5 = tmp_path / 'episode_20240102-030405.hdf5'
    assert run([str(bag_path), '--rate', '10', '--cameras', 'right_hand_camera']) == 0
    assert list(read_images(hdf5)) == ['right_hand_camera']
    assert run([str(bag_path), '--rate', '10', '--no-images']) == 0
    assert read_images(hdf5) == {}
    assert run([str(bag_path), '--rate', '10', '--cameras', 'room_camera,head_camera']) == 1
    assert 'no frames of head_camera in the bag' in capsys.readouterr().err
    assert read_images(hdf5) == {}  # the failed export left the previous file alone


def test_an_episode_without_cameras_gets_an_empty_images_group(tmp_path):
    assert run([str(write_episode(tmp_path)), '--rate', '10']) == 0
    assert read_images(tmp_path / 'episode_20240102-030405.hdf5') == {}


def test_camera_options_need_the_hdf5_and_exclude_each_other(capsys):
    for argv in (['e', '--cameras', 'a', '--no-images'], ['e', '--format', 'csv', '--no-images'],
                 ['e', '--cameras', ','], ['e', '--image-size', '320'],
                 ['e', '--image-size', '8x8'], ['e', '--format', 'csv', '--image-size', 'full'],
                 ['e', '--plot', '--format', 'csv', '--act-dir', 'd']):
        with pytest.raises(SystemExit):
            export_cli.parse_args(argv)
    assert export_cli.parse_args(['e', '--cameras', 'a, b']).cameras == ['a', 'b']
    assert export_cli.parse_args(['e']).cameras is None
    capsys.readouterr()


def test_images_are_scaled_to_320x240_by_default_or_to_the_size_asked(tmp_path):
    bag_path = write_episode(tmp_path)
    add_frames(bag_path, [('room_camera', 0.0, 'red'), ('room_camera', 0.5, 'green')])
    hdf5 = tmp_path / 'episode_20240102-030405.hdf5'
    assert run([str(bag_path), '--rate', '10']) == 0
    room, chunks, _ = read_images(hdf5)['room_camera']
    assert room.shape == (11, 240, 320, 3) and chunks == (1, 240, 320, 3)
    assert colours(room) == ['red'] * 5 + ['green'] * 6
    assert run([str(bag_path), '--rate', '10', '--image-size', '64x48',
                '--compression', 'gzip']) == 0
    room, chunks, compression = read_images(hdf5)['room_camera']
    assert room.shape == (11, 48, 64, 3) and compression == 'gzip'
    assert export_cli.parse_args(['e', '--image-size', 'full']).image_size is None
    assert export_cli.parse_args(['e', '--image-size', '640x480']).image_size == (640, 480)


def test_the_size_is_said_before_writing_and_a_big_file_needs_yes(tmp_path, capsys,
                                                                 monkeypatch):
    bag_path = write_episode(tmp_path)
    add_frames(bag_path, [('room_camera', 0.0, 'red'), ('right_hand_camera', 0.0, 'blue')])
    hdf5 = tmp_path / 'episode_20240102-030405.hdf5'
    assert run([str(bag_path), '--rate', '10', '--image-size', 'full',
                '--compression', 'none']) == 0
    out = capsys.readouterr().out
    # 11 steps x (4 row datasets of 16 float32 + 2 raw 32x24 RGB images)
    expected = 11 * (4 * 16 * 4 + 2 * 32 * 24 * 3)
    assert ('the HDF5 will be about 54 kB: 11 steps x 2 cameras (right_hand_camera 32x24, '
            'room_camera 32x24), 2 kB an image (uncompressed') in out and expected == 53504
    assert out.index('the HDF5 will be about') < out.index('images of ')
    assert abs(hdf5.stat().st_size - expected) < 0.1 * expected + 20000  # within HDF5's own
    hdf5.unlink()
    monkeypatch.setattr(export_size, 'LIMIT_BYTES', 1000.0)
    assert run([str(bag_path), '--rate', '10']) == 1
    err = capsys.readouterr().err
    assert 'the HDF5 would be about' in err and 'add --yes to write it' in err
    assert not hdf5.exists()
    assert run([str(bag_path), '--rate', '10', '--yes']) == 0
    assert hdf5.exists()
    capsys.readouterr()
    assert run([str(bag_path), '--format', 'csv']) == 0  # no HDF5: nothing to estimate
    assert 'the HDF5 will be' not in capsys.readouterr().out
