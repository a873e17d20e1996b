"""ghost: a translucent second Baxter in RViz that shows where the puppet would take the robot.

ghost_urdf renames every link and joint of Baxter's URDF with a prefix (the ghost's own tf
frames); ghost_pose maps the puppet arms' angles onto Baxter's arms exactly as arm/ does
(arm.joint_motion's mirror and clamp); ghost_node publishes them as the ghost's joint states.
"""
