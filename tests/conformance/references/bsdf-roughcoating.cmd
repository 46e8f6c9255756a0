# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 26 s
mitsuba -q -p 2 -Dspp=2048 scenes/bsdf-roughcoating.xml -o references/bsdf-roughcoating.pfm
