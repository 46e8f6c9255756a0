# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 83 s
mitsuba -q -p 1 -Dspp=4096 scenes/light-sunsky.xml -o references/light-sunsky.pfm
