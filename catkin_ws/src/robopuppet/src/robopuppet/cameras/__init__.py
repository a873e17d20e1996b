"""Cameras: the images the nurse sees of the patient's room and of what the gripper will touch.

Every camera publishes sensor_msgs/CompressedImage (JPEG) on /cameras/<name>/image/compressed and
sensor_msgs/CameraInfo on /cameras/<name>/camera_info (interface.camera_topic). See
docs/cameras.md.
"""
