"""Shared pytest set-up: Debian ships both PyQt5 and PyQt6; the GUI (and so pytest-qt) uses PyQt5.

This must happen here, before pytest-qt configures itself; a test module is too late.
"""
import os

os.environ.setdefault('PYTEST_QT_API', 'pyqt5')


def pytest_configure(config):
    # `./test.sh unit` (the quick loop) leaves these out; `./test.sh` runs them.
    config.addinivalue_line('markers', 'slow: a heavy property test (tens of seconds)')
