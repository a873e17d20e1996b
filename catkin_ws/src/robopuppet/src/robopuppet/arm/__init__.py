"""arm_X's subsystem: the teleoperation state machine, joint motion limits and the node driving Baxter."""
