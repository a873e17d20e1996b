"""serial_X's subsystem: the puppet's serial frames, the link, state sets, device settings and the node."""
