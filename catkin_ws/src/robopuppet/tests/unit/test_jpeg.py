"""robopuppet.cameras.jpeg: the JPEG settings give the advertised size and quality."""
import cv2
import numpy as np
import pytest

from robopuppet.cameras import image_params, jpeg


def scene(width=640, height=480):
    """Return a BGR test image with edges and gradients (JPEG size depends on detail)."""
    y, x = np.indices((height, width))
    image = np.stack([(x * 255 // width), (y * 255 // height), ((x ^ y) & 0xFF)], axis=2)
    image = image.astype(np.uint8)
    cv2.circle(image, (width // 2, height // 2), min(width, height) // 4, (255, 255, 255), 3)
    return image


@pytest.mark.parametrize('quality', [1, 20, 50, 51, 80, 95, 100])
def test_the_estimated_quality_is_the_quality_encoded(quality):
    assert jpeg.quality_of(jpeg.encode(scene(), quality)) == quality


@pytest.mark.parametrize('size', [(640, 480), (320, 240), (1280, 720), (160, 120)])
def test_fit_then_encode_gives_the_advertised_size(size):
    width, height = size
    data = jpeg.encode(jpeg.fit(scene(640, 480), width, height), 80)
    decoded = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
    assert decoded.shape == (height, width, 3)


def test_fit_keeps_an_image_of_the_right_size_as_it_is():
    image = scene(320, 240)
    assert jpeg.fit(image, 320, 240) is image


def test_a_higher_quality_gives_more_bytes_and_a_closer_image():
    image = scene()
    sizes, errors = [], []
    for quality in (20, 50, 80, 95):
        data = jpeg.encode(image, quality)
        decoded = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
        sizes.append(len(data))
        errors.append(float(np.abs(decoded.astype(int) - image.astype(int)).mean()))
    assert sizes == sorted(sizes) and len(set(sizes)) == 4
    assert errors == sorted(errors, reverse=True)


@pytest.mark.parametrize('value', [0, 101, -5, 80.5, '80', None, True])
def test_a_bad_quality_is_refused_with_the_parameter_named(value):
    with pytest.raises(ValueError, match='~quality'):
        image_params.quality(value)


def test_a_whole_float_quality_is_accepted():
    assert image_params.quality(75.0) == 75


@pytest.mark.parametrize('value', [15, 4097, 640.5, '640', None, False])
def test_a_bad_image_side_is_refused_with_the_parameter_named(value):
    with pytest.raises(ValueError, match='~width must be a whole number of pixels in 16..4096'):
        image_params.pixels('width', value)


def test_encoding_nothing_raises_a_jpeg_error():
    with pytest.raises(jpeg.JpegError):
        jpeg.encode(np.zeros((0, 0, 3), np.uint8), 80)


@pytest.mark.parametrize('data', [b'', b'not a jpeg', b'\xff\xd8\xff\xda\x00\x02'])
def test_quality_of_bytes_without_a_table_raises(data):
    with pytest.raises(jpeg.JpegError):
        jpeg.quality_of(data)


@pytest.mark.parametrize('encoding, channels', [('bgr8', 3), ('rgb8', 3), ('bgra8', 4),
                                                ('rgba8', 4), ('mono8', 1)])
def test_raw_images_become_bgr_with_padded_rows(encoding, channels):
    width, height, pad = 5, 3, 4
    bgr = scene(width, height)
    pixels = {'bgr8': bgr, 'rgb8': bgr[:, :, ::-1],
              'bgra8': np.dstack([bgr, np.full((height, width), 255, np.uint8)]),
              'rgba8': np.dstack([bgr[:, :, ::-1], np.full((height, width), 255, np.uint8)]),
              'mono8': bgr[:, :, :1]}[encoding]
    step = width * channels + pad
    rows = np.zeros((height, step), np.uint8)
    rows[:, :width * channels] = pixels.reshape(height, width * channels)
    out = jpeg.raw_to_bgr(encoding, width, height, step, rows.tobytes())
    expected = np.repeat(bgr[:, :, :1], 3, axis=2) if encoding == 'mono8' else bgr
    assert out.shape == (height, width, 3)
    assert np.array_equal(out, expected)


def test_a_raw_image_of_an_unknown_encoding_or_too_few_bytes_is_refused():
    with pytest.raises(jpeg.JpegError, match='unsupported'):
        jpeg.raw_to_bgr('yuv422', 4, 4, 8, bytes(32))
    with pytest.raises(jpeg.JpegError, match='needs 48 bytes'):
        jpeg.raw_to_bgr('bgr8', 4, 4, 12, bytes(47))
