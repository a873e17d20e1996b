"""The recorder's episodes one after another: start, write, flush, stop, and every refusal.

No rospy and no clock: the node passes times in and the file operations (recorder_params.FILES,
or a test's fakes) as an object. A failure to write never raises out of here: the episode stops
and the Status says why, so that the node keeps running.
"""
import os
import time

from robopuppet.episodes import recording


class Recorder:
    """Record one episode at a time into a directory.

    Not thread safe: the node calls it under one lock.

    Args:
        directory: where episodes go (created when missing).
        sides: the puppet sides recorded (recording.parse_sides).
        cameras: the cameras recorded (recording.parse_cameras), for the metadata.
        min_free_mb: free space (MB) below which an episode neither starts nor goes on.
        files: BagWriter(directory, name) (write(topic, msg, stamp_s) -> bytes, flush(),
            size_bytes(), close(), abandon(), .path), write_metadata(path, dict) and
            free_bytes(directory), as in recorder_params.FILES; each may raise OSError.
        task: the task of an episode started without one (~task; checked at each start).
    """

    def __init__(self, directory, sides, cameras, min_free_mb, files, task=''):
        self.directory = directory
        self.task = task
        self.sides = tuple(sides)
        self.cameras = tuple(cameras)
        self.min_free_mb = min_free_mb
        self._files = files
        self._writer = None
        self._episode = None
        self._meta = None
        self._last = recording.IDLE

    def recording(self):
        """Return True while an episode is open."""
        return self._writer is not None

    def start(self, notes, stamp_s, wall_s, comm_rate_hz, ini_fingerprints, sim, task=''):
        """Open a new episode at ROS time stamp_s and Unix time wall_s (s).

        comm_rate_hz, ini_fingerprints and sim go into the metadata (recording.metadata), and
        the task (recording.check_task; '' or blank: self.task).
        Returns:
            (ok, error, episode bag file): refused (ok False) while recording, for a task that
            is not one printable line, when the disk is nearly full or the directory cannot be
            written.
        """
        if self._writer is not None:
            return False, 'already recording %s' % self._writer.path, self._writer.path
        try:
            task = recording.check_task(task)
        except ValueError as error:
            return self.refuse(str(error))
        if not task:
            try:
                task = recording.check_task(self.task)
            except ValueError as error:
                return self.refuse("the recorder's ~task is not valid (give a task with the "
                                   "start, or fix ~task): %s" % error)
        try:
            os.makedirs(self.directory, exist_ok=True)
            problem = recording.disk_problem(self._files.free_bytes(self.directory),
                                             self.min_free_mb)
        except OSError as error:
            problem = 'cannot use %s: %s' % (self.directory, error)
        if problem:
            return self.refuse(problem)
        name = recording.episode_name(time.localtime(wall_s),
                                      lambda n: recording.files_taken(self.directory, n))
        meta = recording.metadata(name, wall_s, stamp_s, 0.0, self.sides, self.cameras,
                                  comm_rate_hz, ini_fingerprints, notes, False, sim, {}, task)
        try:
            writer = self._files.BagWriter(self.directory, name)
        except OSError as error:
            return self.refuse('cannot write %s: %s' % (self.directory, error))
        try:
            self._files.write_metadata(self._meta_path(name), meta)
        except OSError as error:
            writer.abandon()
            return self.refuse('cannot write the metadata of %s: %s' % (name, error))
        self._writer, self._meta = writer, meta
        self._episode = recording.Episode(name, stamp_s, notes)
        return True, '', writer.path

    def write(self, topic, msg, stamp_s):
        """Write a message received on topic at ROS time stamp_s (s), when recording.

        Returns:
            True when the write failed and so stopped the episode.
        """
        if self._writer is None:
            return False
        try:
            self._writer.write(topic, msg, stamp_s)
        except OSError as error:
            self._fail('writing %s failed: %s' % (topic, error), stamp_s)
            return True
        self._episode.count(topic, stamp_s)
        return False

    def tick(self, stamp_s):
        """Flush the bag and check the free space (call at least once a second)."""
        if self._writer is None:
            return
        try:
            self._writer.flush()
            problem = recording.disk_problem(self._files.free_bytes(self.directory),
                                             self.min_free_mb)
        except OSError as error:
            problem = 'writing %s failed: %s' % (self._writer.active_path, error)
        if problem:
            self._fail(problem, stamp_s)

    def stop(self, notes, stamp_s, problem=''):
        """Close the episode at ROS time stamp_s (s); notes, when not empty, replace the notes.

        Returns:
            (ok, error, episode bag file).
        """
        if self._writer is None:
            return False, 'not recording', self._last.episode
        writer, episode, self._writer = self._writer, self._episode, None
        self._meta.update(duration_s=max(0.0, stamp_s - episode.start_stamp_s),
                          topics=dict(sorted(episode.topics.items())), ended_cleanly=True)
        if notes:
            self._meta['notes'] = notes
        try:
            writer.close()
            self._files.write_metadata(self._meta_path(episode.name), self._meta)
        except OSError as error:
            writer.abandon()
            problem = 'closing %s failed (it is repaired at the next start): %s' % (
                episode.name, error)
        self._last = episode.status(writer.path, stamp_s, writer.size_bytes(), False, problem)
        return not problem, problem, writer.path

    def status(self, stamp_s):
        """Return the recording.Status at ROS time stamp_s (s)."""
        if self._writer is None:
            return self._last
        return self._episode.status(self._writer.path, stamp_s, self._writer.size_bytes())

    def _fail(self, problem, stamp_s):
        self.stop('', stamp_s, problem)

    def refuse(self, problem):
        """Refuse an episode for problem (also one the node found: the folder is not locked).

        Returns:
            (False, problem, ''); the status's problem says it.
        """
        self._last = self._last._replace(recording=False, problem=problem)
        return False, problem, ''

    def _meta_path(self, name):
        return os.path.join(self.directory, name + recording.META)
