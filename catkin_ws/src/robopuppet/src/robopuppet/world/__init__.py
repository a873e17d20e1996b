"""Baxter's surroundings: shape files in its base frame, the arm as capsules, keep-out zones."""
