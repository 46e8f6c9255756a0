# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 7 s
mitsuba -q -p 2 -Dspp=4096 scenes/light-sun-directional.xml -o references/light-sun-directional.pfm
