"""arm_X's subsystem: the teleop state machine, joint motion limits, the node driving Baxter."""
