"""Camera frames to MP4 video with Debian's ffmpeg, through a pipe: raw RGB frames in, one
encoded file out; episodes' files joined into one by stream copy (ffmpeg's concat demuxer, as
LeRobot joins its episodes' videos).

Codecs (docs/demonstrations.md, "LeRobot dataset"): h264 (libx264) by default: it encodes
three 640x480 cameras faster than real time on one core and every decoder reads it (OpenCV,
PyAV, torchvision, browsers); av1 (libsvtav1), LeRobot's default, is smaller and slower to
encode. Both yuv420p (what every decoder and LeRobot's own videos use; it needs even widths
and heights) and a keyframe every 2 frames (LeRobot's g=2: a frame at any timestamp decodes
from at most one frame before it).
"""
import os
import shutil
import subprocess
import tempfile

PIX_FMT = 'yuv420p'
GOP = 2
CODECS = {  # --video-codec: the codec's name in info.json, ffmpeg's encoder and its options
    'h264': {'codec': 'h264', 'encoder': 'libx264', 'crf': 23, 'preset': 'veryfast'},
    'av1': {'codec': 'av1', 'encoder': 'libsvtav1', 'crf': 30, 'preset': '10'},
}
DEFAULT_CODEC = 'h264'


class VideoError(OSError):
    """ffmpeg is missing, or it failed to encode or join videos."""


def ffmpeg():
    """Return the path of ffmpeg.

    Raises:
        VideoError: it is not installed.
    """
    path = shutil.which('ffmpeg') or ('/usr/bin/ffmpeg' if os.path.exists('/usr/bin/ffmpeg')
                                      else None)
    if path is None:
        raise VideoError('ffmpeg is not installed: run tools/setup.sh (it installs Debian\'s '
                         'ffmpeg) or apt-get install ffmpeg')
    return path


def settings(codec):
    """Return the info.json settings of a codec: codec, pix_fmt, g, crf, preset."""
    chosen = CODECS[codec]
    return {'codec': chosen['codec'], 'pix_fmt': PIX_FMT, 'g': GOP, 'crf': chosen['crf'],
            'preset': chosen['preset']}


class Encoder:
    """One video file written as frames come: write(image) each frame (H, W, 3) uint8 RGB of
    the size given, then close(), which waits for ffmpeg.

    Raises (from write and close):
        VideoError: ffmpeg failed (its last lines in the message), e.g. a full disk.
    """

    def __init__(self, path, size, fps, codec=DEFAULT_CODEC):
        width, height = size
        if width % 2 or height % 2:
            raise VideoError('%dx%d: %s video needs an even width and height (give '
                             '--image-size)' % (width, height, PIX_FMT))
        chosen = CODECS[codec]
        self.path, self.frames, self.size = path, 0, (width, height)
        self._log = tempfile.TemporaryFile()
        command = [ffmpeg(), '-hide_banner', '-loglevel', 'error', '-nostdin', '-y',
                   '-f', 'rawvideo', '-pix_fmt', 'rgb24', '-s', '%dx%d' % (width, height),
                   '-framerate', str(int(fps)), '-i', 'pipe:0',
                   '-c:v', chosen['encoder'], '-pix_fmt', PIX_FMT, '-g', str(GOP),
                   '-crf', str(chosen['crf']), '-preset', chosen['preset'],
                   '-f', 'mp4', path]
        self._process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=self._log,
                                         stderr=self._log)

    def write(self, image, repeat=1):
        """Write an image as the next repeat frames."""
        if (image.shape[1], image.shape[0]) != self.size:
            raise VideoError('a %dx%d frame in a %dx%d video' % (
                image.shape[1], image.shape[0], self.size[0], self.size[1]))
        data = image.tobytes()
        try:
            for _ in range(repeat):
                self._process.stdin.write(data)
        except BrokenPipeError as error:
            raise VideoError('ffmpeg stopped encoding %s: %s' % (self.path,
                                                                 self._errors())) from error
        self.frames += repeat

    def close(self):
        """Finish the file; return its frame count."""
        try:
            self._process.stdin.close()
        except BrokenPipeError:
            pass
        if self._process.wait() != 0:
            raise VideoError('ffmpeg failed to encode %s: %s' % (self.path, self._errors()))
        self._log.close()
        return self.frames

    def abort(self):
        """Stop ffmpeg without finishing the file."""
        if self._process.poll() is None:
            self._process.kill()
            self._process.wait()
        self._log.close()

    def _errors(self):
        self._process.poll()
        self._log.seek(0)
        lines = self._log.read().decode('utf-8', 'replace').strip().splitlines()
        return ' / '.join(lines[-3:]) or 'exit code %s' % self._process.returncode


def join(paths, out_path):
    """Write the videos at paths, one after the other, into out_path (stream copy: no
    re-encoding; they must share codec, size and rate). One path is just moved.

    Raises:
        VideoError: ffmpeg failed.
    """
    if len(paths) == 1:
        os.replace(paths[0], out_path)
        return
    with tempfile.NamedTemporaryFile('w', suffix='.txt', dir=os.path.dirname(out_path),
                                     delete=False) as listing:
        for path in paths:
            listing.write("file '%s'\n" % os.path.abspath(path).replace("'", "'\\''"))
    try:
        result = subprocess.run([ffmpeg(), '-hide_banner', '-loglevel', 'error', '-nostdin',
                                 '-y', '-f', 'concat', '-safe', '0', '-i', listing.name,
                                 '-c', 'copy', '-f', 'mp4', out_path],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, check=False)
    finally:
        os.remove(listing.name)
    if result.returncode != 0:
        raise VideoError('ffmpeg failed to join %d videos into %s: %s' % (
            len(paths), out_path, result.stdout.decode('utf-8', 'replace').strip()[-300:]))
    for path in paths:
        os.remove(path)
