# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 20 s
mitsuba -q -p 2 -Dspp=4096 scenes/light-envmap-gamma.xml -o references/light-envmap-gamma.pfm
