"""Guided calibration: each joint's home_angle and sign_angle solved from captured poses."""
