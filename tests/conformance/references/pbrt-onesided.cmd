# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 10 s
mitsuba -q -p 2 -Dspp=4096 scenes/pbrt-onesided.xml -o references/pbrt-onesided.pfm
