"""Upkeep of the Mitsuba 0.6 conformance suite (tests/conformance/): its scenes, Mitsuba's
reference images, the docs' tables, the public-scene check and the preset checks."""
