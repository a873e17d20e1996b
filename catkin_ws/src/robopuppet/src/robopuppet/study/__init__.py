"""The user-study kit: other input devices in the puppet's place, standard tasks, the study runner
and the simulated participant (docs/study.md)."""
