"""config_X's subsystem: one ini file per arm (store, atomic file) and the node that serves it."""
