# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 22 s
mitsuba -q -p 2 -Dspp=2048 scenes/bsdf-normalmap.xml -o references/bsdf-normalmap.pfm
