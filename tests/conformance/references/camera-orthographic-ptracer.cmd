# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 67 s
mitsuba -q -p 2 -Dspp=4096 scenes/camera-orthographic-ptracer.xml -o references/camera-orthographic-ptracer.pfm
