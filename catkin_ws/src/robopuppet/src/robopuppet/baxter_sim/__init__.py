"""baxter_sim's subsystem: the kinematic Baxter stand-in (arms, grippers, refusals) and its node."""
