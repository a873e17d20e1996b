"""puppet_sim_X's subsystem: the simulated 2020 firmware, the puppet's physics, wire, node."""
