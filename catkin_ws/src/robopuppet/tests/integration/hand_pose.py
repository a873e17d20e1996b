"""The operator's hand pose of the tests and benchmarks that drive Baxter (imported by them).

No imports, so that the network tests' pytest process, which loads no ROS client library, can
use it too.
"""

# Puppet angles (rad, s0 .. w2): every joint 0.2-0.45 rad from Baxter's neutral pose, the arm
# raised. With config/zones.yaml (on by default) both Baxter arms (the left one mirrored) stay
# clear of every zone on their way from neutral (never nearer than there: right 6.9 cm, left
# 5.4 cm) and around the pose (joint 0 +-0.3 and joint 3 +-0.5 rad, the tests' swings: 17 cm or
# more); tests/unit/test_hand_pose.py checks it.
HAND_POSE = [-0.2, -1.0, -0.3, 1.0, -0.3, 0.9, 0.25]
