"""Demonstration episodes: recording (and export). The episode format is fixed in
docs/demonstrations.md, section "The episode format": the recorder and the exporter follow it."""
