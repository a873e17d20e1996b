"""What an episode's HDF5 will cost, said before it is written: steps x cameras x the stored
size of one image, measured on each camera's first frame (decoded, scaled and compressed as
the export will).

Images are nearly all of the file: every grid step holds a whole image per camera (ALOHA's
layout: ACT reads one step's image by its index), so a camera at 15 frames/s on a 50 Hz grid
stores each frame 3 or 4 times. Pure (numpy, OpenCV, h5py in memory; no ROS).
"""
import collections
import re

import numpy as np

from robopuppet.episodes import export_images
from robopuppet.episodes.export import COLUMNS

DEFAULT_IMAGE_SIZE = (320, 240)   # W, H: a quarter of the cameras' 640x480
LIMIT_BYTES = 1e9                 # above this estimate the export needs --yes
ROW_BYTES = 4 * 4 * len(COLUMNS)  # qpos, qvel, effort, action: float32 each
_SIZE_RE = re.compile(r'^\s*(\d+)\s*[xX]\s*(\d+)\s*$')

Estimate = collections.namedtuple('Estimate', 'steps images total_bytes')
Estimate.__doc__ = """An HDF5's estimated size: steps (grid steps), images ({camera: (W, H,
stored bytes of one image)}), total_bytes."""


class SizeError(ValueError):
    """An image size that is not WxH nor 'full'."""


def parse_size(text):
    """Return an --image-size as (W, H) in pixels; None for 'full' (as recorded).

    Raises:
        SizeError: not WxH with both from 16 to 4096, nor 'full'.
    """
    if text.strip().lower() == 'full':
        return None
    match = _SIZE_RE.match(text)
    if not match or not all(16 <= int(n) <= 4096 for n in match.groups()):
        raise SizeError('give the image size as WxH (e.g. 320x240, 640x480; 16 to 4096 '
                        'pixels each) or full, got %r' % text)
    return int(match.group(1)), int(match.group(2))


def stored_bytes(image, compression):
    """Return the bytes one image (H, W, 3) uint8 takes in an HDF5 chunk of its own with the
    filter compression (None: raw), as Hdf5File stores it."""
    if compression is None:
        return image.nbytes
    import h5py  # pylint: disable=import-outside-toplevel  (the replay command skips it)
    with h5py.File('estimate', 'w', driver='core', backing_store=False) as root:
        dataset = root.create_dataset('image', (1,) + image.shape, dtype=np.uint8,
                                      chunks=(1,) + image.shape, compression=compression)
        dataset[0] = image
        return len(dataset.id.read_direct_chunk((0, 0, 0, 0))[1])


def sample_images(frames, cameras, size):
    """Return {camera: its first frame that decodes, scaled to size (W, H; None: as
    recorded)} from frames ((camera, t, JPEG bytes) in time order), reading only until every
    camera has one; a camera without one is left out."""
    found = {}
    for camera, _, data in frames:
        if camera in cameras and camera not in found:
            image = export_images.decode(data)
            if image is not None:
                found[camera] = export_images.scale(image, size)
        if len(found) == len(cameras):
            break
    return found


def estimate(steps, images, compression):
    """Return the Estimate of an HDF5 of steps grid steps with the images ({camera: a sample
    image (H, W, 3)}) stored with compression."""
    stored = {camera: (image.shape[1], image.shape[0], stored_bytes(image, compression))
              for camera, image in images.items()}
    total = steps * (ROW_BYTES + sum(b for _, _, b in stored.values()))
    return Estimate(steps, stored, total)


def text(estimate_, compression):
    """Return the line that says what the HDF5 will cost, e.g. 'the HDF5 will be about 212 MB:
    1001 steps x 3 cameras (room_camera 320x240, ...), 71 kB an image (lzf, measured on each
    camera's first frame)'."""
    if not estimate_.images:
        return 'the HDF5 will be about %s: %d steps, no images' % (
            megabytes(estimate_.total_bytes), estimate_.steps)
    per_image = np.mean([b for _, _, b in estimate_.images.values()])
    return ('the HDF5 will be about %s: %d steps x %d camera%s (%s), %.0f kB an image (%s, '
            'measured on each camera\'s first frame)' % (
                megabytes(estimate_.total_bytes), estimate_.steps, len(estimate_.images),
                's' if len(estimate_.images) > 1 else '',
                ', '.join('%s %dx%d' % (camera, w, h)
                          for camera, (w, h, _) in sorted(estimate_.images.items())),
                per_image / 1e3, compression or 'uncompressed'))


def megabytes(count):
    """Return a byte count as text in MB or GB."""
    if count >= 1e9:
        return '%.1f GB' % (count / 1e9)
    if count >= 1e7:
        return '%.0f MB' % (count / 1e6)
    return '%.1f MB' % (count / 1e6) if count >= 1e5 else '%.0f kB' % (count / 1e3)


def too_big(estimate_):
    """Return why an estimate needs --yes (the ways to shrink it), or '' when it does not."""
    if estimate_.total_bytes <= LIMIT_BYTES:
        return ''
    return ('more than %s: add --yes to write it, or make it smaller with --image-size '
            '(e.g. 320x240), --cameras, --rate 15 (the cameras\' rate), --compression gzip or '
            '--no-images' % megabytes(LIMIT_BYTES))
