"""sim_cameras' Baxter camera services (/cameras/list, open, close) and the topics of each camera
that streams: a camera's topics exist only while it is open, as on a real Baxter."""
import threading

import rospy
from baxter_core_msgs.srv import (CloseCamera, CloseCameraResponse, ListCameras,
                                  ListCamerasResponse, OpenCamera, OpenCameraResponse)

from robopuppet import interface
from robopuppet.cameras import camera_service, camera_topics, sim_cameras


def loop_rate_hz(settings):
    """Return the render loop's rate (Hz): fast enough for ~rate and any fps open accepts."""
    return max(settings.rate_hz, camera_service.MAX_FPS)


class CameraServices:
    """Serve Baxter's camera services for the simulated cameras (camera_service's rules) and
    keep the topics of the cameras that stream.

    Hold `lock` while using topics(): a service call changes them under it.

    Serves: /cameras/list (baxter_core_msgs/ListCameras), /cameras/open (OpenCamera: a mode of
        Baxter's, fps in (0, 30]; controls are taken and not modelled), /cameras/close
        (CloseCamera). A refusal answers a non-zero err and logs a warning saying why.

    Args:
        core: the sim_cameras.SimCameras that renders them (set_size on open).
        settings: sim_cameras.Settings: every camera streams at width x height, rate_hz from
            the start.
    """

    def __init__(self, core, settings):
        self.lock = threading.Lock()
        self._core = core
        self._name = rospy.get_name()
        self._service = camera_service.CameraService(list(core.cameras), camera_service.Mode(
            settings.width, settings.height, settings.rate_hz))
        self._topics = {}
        for name in self._service.streaming():
            self._advertise(name)
        self._servers = [
            rospy.Service(interface.CAMERAS_LIST, ListCameras, self._on_list),
            rospy.Service(interface.CAMERAS_OPEN, OpenCamera, self._on_open),
            rospy.Service(interface.CAMERAS_CLOSE, CloseCamera, self._on_close)]

    def topics(self, now_s):
        """Return {name: CameraTopics} of the streaming cameras whose frame is due at now_s."""
        return {name: topics for name, topics in self._topics.items()
                if self._service.due(name, now_s)}

    def _advertise(self, name):
        width, height = self._core.sizes[name]
        self._topics[name] = camera_topics.CameraTopics(name, sim_cameras.camera_info_fields(
            self._core.cameras[name], width, height), True)

    def _on_list(self, _request):
        with self.lock:
            return ListCamerasResponse(self._service.cameras())

    def _on_open(self, request):
        settings = request.settings
        with self.lock:
            answer = self._service.open(request.name, settings.width, settings.height,
                                        settings.fps)
            if answer.err == camera_service.OK:
                if (settings.width, settings.height) != self._core.sizes[request.name] or \
                        request.name not in self._topics:
                    self._withdraw(request.name)
                    self._core.set_size(request.name, settings.width, settings.height)
                    self._advertise(request.name)
        self._log(answer)
        return OpenCameraResponse(answer.err)

    def _on_close(self, request):
        with self.lock:
            answer = self._service.close(request.name)
            if answer.err == camera_service.OK:
                self._withdraw(request.name)
        self._log(answer)
        return CloseCameraResponse(answer.err)

    def _withdraw(self, name):
        topics = self._topics.pop(name, None)
        if topics is not None:
            topics.unregister()

    def _log(self, answer):
        if answer.err == camera_service.OK:
            rospy.loginfo('%s: %s', self._name, answer.line)
        else:
            rospy.logwarn('%s: refused (err %d): %s', self._name, answer.err, answer.line)
