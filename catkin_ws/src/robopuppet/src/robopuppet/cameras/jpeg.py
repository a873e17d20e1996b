"""JPEG for the camera topics: encode settings, raw-image conversion and a quality estimate.

Pure (OpenCV and numpy, no ROS). The format string follows image_transport's 'compressed'
convention, which image_view and RViz's camera tools decode.
"""
import cv2
import numpy as np

# sensor_msgs/CompressedImage.format of a JPEG made from a bgr8 image (compressed_image_transport)
JPEG_FORMAT = 'bgr8; jpeg compressed bgr8'

# sensor_msgs/Image encoding -> (bytes per pixel, OpenCV conversion to BGR or None)
RAW_ENCODINGS = {
    'bgr8': (3, None),
    'rgb8': (3, cv2.COLOR_RGB2BGR),
    'bgra8': (4, cv2.COLOR_BGRA2BGR),  # Baxter's own cameras
    'rgba8': (4, cv2.COLOR_RGBA2BGR),
    'mono8': (1, cv2.COLOR_GRAY2BGR),
}

# The IJG (libjpeg) luminance quantisation table at quality 50, in the zigzag order of DQT.
_LUMA_ZIGZAG = (16, 11, 12, 14, 12, 10, 16, 14, 13, 14, 18, 17, 16, 19, 24, 40, 26, 24, 22, 22,
                24, 49, 35, 37, 29, 40, 58, 51, 61, 60, 57, 51, 56, 55, 64, 72, 92, 78, 64, 68,
                87, 69, 55, 56, 80, 109, 81, 87, 95, 98, 103, 104, 103, 62, 77, 113, 121, 112,
                100, 120, 92, 101, 103, 99)


class JpegError(ValueError):
    """An image could not be encoded, or bytes are not a JPEG this module understands."""


def fit(image, width, height):
    """Return a BGR image of exactly width x height pixels (resized if it is not already)."""
    if image.shape[1] == width and image.shape[0] == height:
        return image
    # INTER_AREA where it matters (half size or less); at a slight shrink it is ~8 times slower.
    halved = 2 * width <= image.shape[1] and 2 * height <= image.shape[0]
    return cv2.resize(image, (width, height),
                      interpolation=cv2.INTER_AREA if halved else cv2.INTER_LINEAR)


def encode(image, quality):
    """Return the JPEG bytes of a BGR (or grey) numpy image at a quality in 1..100.

    Raises:
        JpegError: OpenCV could not encode the image (empty, wrong type).
    """
    try:
        ok, data = cv2.imencode('.jpg', image, [cv2.IMWRITE_JPEG_QUALITY, int(quality)])
    except cv2.error as error:
        raise JpegError('cannot encode the image as JPEG: %s' % error) from None
    if not ok:
        raise JpegError('cannot encode the image as JPEG')
    return data.tobytes()


def raw_to_bgr(encoding, width, height, step, data):
    """Return a sensor_msgs/Image's pixels as a BGR numpy image (height, width, 3).

    Args:
        encoding: one of RAW_ENCODINGS (bgra8 is what Baxter's cameras publish).
        width, height: pixels; step: bytes per row (rows may be padded); data: the bytes.
    Raises:
        JpegError: unknown encoding, or data too short for the size.
    """
    if encoding not in RAW_ENCODINGS:
        raise JpegError('unsupported image encoding %r (supported: %s)'
                        % (encoding, ', '.join(sorted(RAW_ENCODINGS))))
    channels, conversion = RAW_ENCODINGS[encoding]
    if width <= 0 or height <= 0 or step < width * channels or len(data) < step * height:
        raise JpegError('a %s image of %dx%d with step %d needs %d bytes, got %d'
                        % (encoding, width, height, step, step * height, len(data)))
    rows = np.frombuffer(data, np.uint8, count=step * height).reshape(height, step)
    pixels = rows[:, :width * channels].reshape(height, width, channels)
    if conversion is None:
        return pixels
    return cv2.cvtColor(np.ascontiguousarray(pixels), conversion)


def _luma_table(data):
    """Return the 64 entries (zigzag order) of the JPEG's first quantisation table (id 0)."""
    at = 2
    if data[:2] != b'\xff\xd8':
        raise JpegError('not a JPEG (no SOI marker)')
    while at + 4 <= len(data):
        if data[at] != 0xFF:
            raise JpegError('corrupt JPEG: no marker at byte %d' % at)
        marker, length = data[at + 1], int.from_bytes(data[at + 2:at + 4], 'big')
        if marker == 0xDB:  # DQT: one or more tables
            body, end = at + 4, at + 2 + length
            while body < end:
                precision, table_id = data[body] >> 4, data[body] & 0x0F
                size = 2 if precision else 1
                values = [int.from_bytes(data[body + 1 + i * size:body + 1 + (i + 1) * size],
                                         'big') for i in range(64)]
                if table_id == 0:
                    return values
                body += 1 + 64 * size
        if marker == 0xDA:  # start of scan: no table before the image data
            break
        at += 2 + length
    raise JpegError('the JPEG has no luminance quantisation table')


def quality_of(data):
    """Estimate the IJG quality (1..100) a JPEG was encoded with, from its luminance table.

    The inverse of libjpeg's jpeg_quality_scaling: the quality whose scaled standard table is
    nearest. Exact for JPEGs that libjpeg (OpenCV, cameras with libjpeg) wrote with the
    standard tables; a camera's own tables give the nearest IJG quality.

    Raises:
        JpegError: the bytes are not a JPEG with a quantisation table.
    """
    table = _luma_table(bytes(data))
    best, best_error = None, None
    for quality in range(1, 101):
        scale = 5000 // quality if quality < 50 else 200 - 2 * quality
        expected = [min(max((q * scale + 50) // 100, 1), 255 if max(table) < 256 else 32767)
                    for q in _LUMA_ZIGZAG]
        error = sum(abs(a - b) for a, b in zip(table, expected))
        if best_error is None or error < best_error:
            best, best_error = quality, error
    return best
