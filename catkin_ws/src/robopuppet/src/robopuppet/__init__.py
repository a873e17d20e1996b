"""RoboPuppet host software: pure cores (codec, config store, motion models, teleop) and ROS nodes."""
