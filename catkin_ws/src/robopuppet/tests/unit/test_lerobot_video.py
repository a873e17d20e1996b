"""Videos through Debian's ffmpeg: frames in, the same frames decoded out (OpenCV), episodes
joined without re-encoding at exact timestamps, and ffmpeg's failures as VideoError."""
import subprocess

import cv2
import numpy as np
import pytest

from robopuppet.episodes import lerobot_video


def frames(count, shade=0):
    """Return count 64x64 RGB frames (SVT-AV1's least), each a different grey (plus shade)."""
    return [np.full((64, 64, 3), 20 + 10 * k + shade, np.uint8) for k in range(count)]


def encode(path, images, codec='h264', fps=10):
    encoder = lerobot_video.Encoder(str(path), (64, 64), fps, codec)
    for image in images:
        encoder.write(image)
    return encoder.close()


def decoded(path):
    capture = cv2.VideoCapture(str(path))
    out = []
    while True:
        ok, image = capture.read()
        if not ok:
            return out
        out.append(image)


def frame_times(path):
    result = subprocess.run(['ffprobe', '-v', 'error', '-select_streams', 'v:0', '-show_entries',
                             'frame=pts_time', '-of', 'csv=p=0', str(path)],
                            capture_output=True, text=True, check=True)
    return [float(line.strip(',')) for line in result.stdout.split()]


@pytest.mark.parametrize('codec', sorted(lerobot_video.CODECS))
def test_frames_come_back_in_order_at_their_times(tmp_path, codec):
    path = tmp_path / 'a.mp4'
    assert encode(path, frames(12), codec) == 12
    images = decoded(path)
    assert len(images) == 12
    means = [image.mean() for image in images]
    assert means == pytest.approx([20 + 10 * k for k in range(12)], abs=2.0)
    assert frame_times(path) == pytest.approx([k / 10 for k in range(12)])


def test_joined_episodes_keep_every_frame_at_its_time(tmp_path):
    first, second = tmp_path / 'a.mp4', tmp_path / 'b.mp4'
    encode(first, frames(7))
    encode(second, frames(5, shade=100))
    out = tmp_path / 'file-000.mp4'
    lerobot_video.join([str(first), str(second)], str(out))
    assert not first.exists() and not second.exists()
    assert frame_times(out) == pytest.approx([k / 10 for k in range(12)])
    means = [image.mean() for image in decoded(out)]
    assert means == pytest.approx([20 + 10 * k for k in range(7)] +
                                  [120 + 10 * k for k in range(5)], abs=2.0)


def test_repeated_frames_and_wrong_sizes(tmp_path):
    encoder = lerobot_video.Encoder(str(tmp_path / 'a.mp4'), (64, 64), 10)
    encoder.write(frames(1)[0], repeat=4)
    with pytest.raises(lerobot_video.VideoError, match='a 16x24 frame in a 64x64 video'):
        encoder.write(np.zeros((24, 16, 3), np.uint8))
    assert encoder.close() == 4
    assert len(decoded(tmp_path / 'a.mp4')) == 4
    with pytest.raises(lerobot_video.VideoError, match='even width and height'):
        lerobot_video.Encoder(str(tmp_path / 'b.mp4'), (33, 24), 10)


def test_an_encoding_that_fails_says_why(tmp_path):
    encoder = lerobot_video.Encoder(str(tmp_path / 'missing' / 'a.mp4'), (64, 64), 10)
    with pytest.raises(lerobot_video.VideoError, match='ffmpeg'):
        for image in frames(50):
            encoder.write(image)
        encoder.close()
    encoder.abort()


def test_settings_for_info_json():
    assert lerobot_video.settings('h264') == {'codec': 'h264', 'pix_fmt': 'yuv420p', 'g': 2,
                                              'crf': 23, 'preset': 'veryfast'}
    assert lerobot_video.settings('av1')['codec'] == 'av1'
