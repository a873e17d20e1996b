"""RoboPuppet host software: one folder per subsystem, each pure cores beside its node adapter.

Data flows from the puppet to Baxter:

    puppet (or puppet_sim/) --serial--> protocol/ (serial_X) --topics--> arm/ (arm_X) --> Baxter
                                             ^                                   (or baxter_sim/)
    config/ (config_X: the ini file) --------+      gui/ (gui_X) watches and tunes all of it

| folder       | may import                   | what it holds                                    |
|--------------|------------------------------|--------------------------------------------------|
| (top level)  | tables                       | interface (names, enumerations, timing), settings |
|              |                              | (the joint settings and their rules), params,    |
|              |                              | baxter_description (URDF), periodic, float32,    |
|              |                              | link_silence (stuck link connections),           |
|              |                              | atomic_file (replaced whole), png_plot           |
| config/      | tables                       | config_X: ini store, settings keeper, the file   |
| protocol/    | tables                       | serial_X: frames, link, state sets, serial core  |
| world/       | tables                       | shape files (world, zones), the arm as capsules, |
|              |                              | clearances, the keep-out zone guard              |
| calibration/ | tables                       | home and sign solved from poses, wizard steps,   |
|              |                              | the terminal command calibrate                   |
| arm/         | tables, world                | arm_X: controller, teleop, puppet/Baxter watches |
| baxter_sim/  | tables, world                | baxter_sim: the kinematic Baxter stand-in        |
| cameras/     | tables, world                | camera, camera_republish, sim_cameras (OpenGL)   |
| puppet_sim/  | tables, protocol             | puppet_sim_X: the simulated 2020 firmware        |
| ghost/       | tables, arm                  | ghost: the puppet's pose on a translucent Baxter |
| episodes/    | tables, arm, config          | recorder, replay, the exporter of episodes       |
| assist/      | tables, arm, world,          | assist: simulated tasks, demonstrations,         |
|              | episodes, baxter_sim         | learners, train_assist, the assist node          |
| study/       | tables, arm, world, protocol,| the user-study kit: input devices in the         |
|              | episodes, baxter_sim, assist | puppet's place, tasks, the runner, the simulated |
|              |                              | participant                                      |
| gui/         | tables, arm, calibration,    | gui_X: the Qt window and its ROS client          |
|              | config, episodes, puppet_sim,|                                                  |
|              | study                        |                                                  |

The subsystems meet only through ROS topics and services named in interface.py (settings reach
serial_X as config_X's active_settings, not as an import); puppet_sim/ shares protocol/'s codec
because it speaks the same wire, and gui/ uses config/'s form checks, puppet_sim/'s rest
pose for its virtual puppet, calibration/'s steps for its wizard and episodes/' status line.
cameras/ reads its world file's shapes and arm/ its keep-out zones through world/, which
holds no node of its own. ghost/ maps the puppet's angles with arm/'s pure joint_motion and
readings, so that the ghost shows exactly what arm_X would command; gui/ maps Baxter's pose back
into puppet space with the same joint_motion rule as arm_X's feel mode.

Only the ROS adapters talk to ROS (import rospy or message packages): each folder's node
(`*_node.py`, imported only by the executables in nodes/) and the modules listed here. The others
are pure: no rospy, no Qt outside gui/, time taken as an argument.

ROS adapters besides the nodes:
- `link_recovery`: subscriptions across the operator-robot link that come back after a cut
- `shape_markers`: RViz markers of shapes (arm_X's zones, sim_cameras' room)
- `config.arm_topics`: config_X's settings topics, its opmode and teleop_state subscriptions
- `protocol.serial_topics`: serial_X's publishers, its diagnostics and its link_ping echo
- `arm.arm_params`: arm_X's ~parameters and the controller made from them
- `arm.command_loop`: arm_X's command loop, its watchdog and the publishers of its actions
- `arm.link_topics`: arm_X's topics of the operator-robot link
- `arm.teleop_topics`: arm_X's teleop_state, its /diagnostics status and zone markers
- `arm.zone_topics`: arm_X's zone file and zone markers
- `baxter_sim.baxter_params`: baxter_sim's parameters, read and made into its BaxterApi
- `baxter_sim.baxter_publishers`: baxter_sim's publishers of each cycle's states
- `puppet_sim.puppet_publishers`: puppet_sim_X's publishers of each device step
- `calibration.arm_reader`: the calibrate command's view of one puppet arm
- `episodes.bag_chunks`: a bag read one chunk at a time
- `episodes.episode_files`: an episode's bag, written raw, and its repair
- `episodes.export_files`: the exporter's and the replay's reads of an episode's bag
- `episodes.player`: what the two episode players share
- `episodes.puppet_player`: playback into the puppet
- `episodes.robot_player`: playback onto the robot
- `episodes.recorder_claim`: the recorder's folder lock and service, claimed before it registers
- `episodes.recorder_params`: the recorder's ~parameters and the metadata's facts of the system
- `assist.sim_hands`: the operator's hands on the simulated puppets (demonstrate, rostests)
- `cameras.camera_topics`: a camera's image topics and fixed cameras' static frames
- `cameras.node_loops`: the loops of a camera node and its /diagnostics
- `cameras.camera_services`: sim_cameras' Baxter camera services and its cameras' topics
- `cameras.marker_shapes`: the solid shapes a MarkerArray draws (the study's task objects)
- `gui.puppet_client`: the GUI's ROS client: services and their answers
- `gui.state_topics`: the GUI's subscriptions of one arm's state
- `gui.command_topics`: the GUI's publishers of one arm's commands
- `gui.assist_topics`: the GUI's subscription of the assist's state
- `gui.study_topics`: the study tab's runner state, Start/Stop service and questionnaire
- `gui.camera_client`: the camera pane's ROS client
- `study.marker_device`: the RViz marker device's interactive marker server and feedback
- `study.task_markers`: a study trial's RViz markers (goals, spots, object, path)
- `study.study_topics`: the study runner's watched topics, StudyState, markers, Record calls
- `study.participant_outputs`: the simulated participant's FIFOs, marker feedback, puppet hands

tests/unit/test_layout.py reads both lists above and holds the tree to them: the imports, and
the sizes (a ROS adapter at most 150 lines, any other module at most 300, with the exceptions
that test names and justifies).
"""
