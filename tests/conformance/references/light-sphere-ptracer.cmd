# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 44 s
mitsuba -q -p 2 -Dspp=4096 scenes/light-sphere-ptracer.xml -o references/light-sphere-ptracer.pfm
