"""The assist: one Baxter arm predicted from the other's motion, learned from demonstrations.

tasks and demonstration hold the simulated bimanual tasks and their scripted demonstrations;
dataset, the learners, model_file and train turn episodes into a model (train_assist);
assist_core decides, and assist_node publishes, what the assisted arm does, which the leading
puppet's arm_X carries out through its own safety path (docs/assist.md).
"""
