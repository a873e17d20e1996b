"""The RoboPuppet GUI (gui_X): PyQt5 window with main, joint and virtual-puppet tabs."""
import os

# Debian installs PyQt6 too; pyqtgraph would pick it when imported first.
os.environ.setdefault('PYQTGRAPH_QT_LIB', 'PyQt5')
