# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 49 s
mitsuba -q -p 1 -Dspp=4096 scenes/light-sky.xml -o references/light-sky.pfm
