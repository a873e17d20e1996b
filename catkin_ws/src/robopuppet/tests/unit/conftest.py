"""Shared pytest set-up: Debian ships both PyQt5 and PyQt6; the GUI (and so pytest-qt) uses PyQt5.

This must happen here, before pytest-qt configures itself; a test module is too late.
"""
import os

os.environ.setdefault('PYTEST_QT_API', 'pyqt5')
