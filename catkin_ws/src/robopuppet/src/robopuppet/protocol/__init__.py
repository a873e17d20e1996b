"""serial_X's subsystem: frames, the link, state sets, settings, its pure core and node."""
