# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 40 s
mitsuba -q -p 2 -Dspp=4096 scenes/light-collimated-ptracer.xml -o references/light-collimated-ptracer.pfm
