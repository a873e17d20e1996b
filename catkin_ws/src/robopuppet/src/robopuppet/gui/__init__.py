"""The RoboPuppet GUI (gui_X): PyQt5 window with main, joint and virtual-puppet tabs."""
