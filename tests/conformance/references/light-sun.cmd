# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 41 s
mitsuba -q -p 1 -Dspp=4096 scenes/light-sun.xml -o references/light-sun.pfm
