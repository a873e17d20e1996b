"""RoboPuppet host software: one folder per subsystem, each pure cores beside its node adapter.

Data flows from the puppet to Baxter:

    puppet (or puppet_sim/) --serial--> protocol/ (serial_X) --topics--> arm/ (arm_X) --> Baxter
                                             ^                                   (or baxter_sim/)
    config/ (config_X: the ini file) --------+      gui/ (gui_X) watches and tunes all of it

| folder        | role                                                        | may import      |
|---------------|-------------------------------------------------------------|-----------------|
| (top level)   | shared tables: interface (names, enumerations, timing),     | tables only     |
|               | settings (the joint settings), baxter_description (URDF),   |                 |
|               | periodic (guarded loops), params (parameter checks),        |                 |
|               | float32 (the settings' wire rounding and text);             |                 |
|               | link_recovery (a shared ROS adapter: subscriptions that     |                 |
|               | come back soon after a link cut); shape_markers (another:   |                 |
|               | RViz markers of shapes, the zones' and the room's)          |                 |
| config/       | config_X: ini store, settings keeper, atomic file, the node | tables          |
| baxter_sim/   | baxter_sim: the kinematic Baxter stand-in and its node      | tables, world   |
| protocol/     | serial_X: frames, link, state sets, serial core, settings   | tables          |
| arm/          | arm_X: controller, teleop, puppet/Baxter watches, timing    | tables, world   |
| puppet_sim/   | puppet_sim_X: the simulated 2020 firmware and its node      | tables,protocol |
| calibration/  | home_angle and sign_angle solved from poses; the wizard's   | tables          |
|               | steps and the terminal command calibrate (calibrate_node)   |                 |
| gui/          | gui_X: the Qt window and its ROS client                     | tables, arm,    |
|               |                                                             | config,         |
|               |                                                             | puppet_sim,     |
|               |                                                             | calibration,    |
|               |                                                             | episodes        |
| ghost/        | ghost: the puppet's pose on a second, translucent Baxter    | tables, arm     |
| episodes/     | recorder: demonstration episodes as rosbags (what, when,    | tables, arm     |
|               | names, metadata, disk rule, the episode's files, repair);   | (the exporter), |
|               | the exporter of episodes                                    | config (the ini |
|               |                                                             | file's path)    |
| cameras/      | camera (webcams), camera_republish, sim_cameras: the        | tables, world   |
|               | stand-in's world file and meshes, rendered by OpenGL        |                 |
| world/        | Baxter's surroundings: the shape-file format (world.yaml,   | tables          |
|               | zones, obstacles), the arm as capsules, clearances, the     |                 |
|               | keep-out zone guard                                         |                 |

The subsystems meet only through ROS topics and services named in interface.py (settings reach
serial_X as config_X's active_settings, not as an import); puppet_sim/ shares protocol/'s codec
because it speaks the same wire, and gui/ uses config/'s form checks, puppet_sim/'s rest
pose for its virtual puppet, calibration/'s steps for its wizard and episodes/' status line.
cameras/ reads its world file's shapes and arm/ its keep-out zones through world/, which
holds no node of its own. ghost/ maps the puppet's angles with arm/'s pure joint_motion and
readings, so that the ghost shows exactly what arm_X would command; gui/ maps Baxter's pose back
into puppet space with the same joint_motion rule as arm_X's feel mode.

Within a folder the node adapter (`*_node.py`) is the only module that talks to ROS (besides
gui.puppet_client, the GUI's ROS client, and the few adapters test_layout.py lists); the others are pure (no rospy, no Qt outside
gui/) and take time as an argument. Only the executables in nodes/ import a `*_node` module.
tests/unit/test_layout.py checks all of this.
"""
