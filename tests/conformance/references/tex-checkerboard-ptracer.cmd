# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 35 s
mitsuba -q -p 2 -Dspp=4096 scenes/tex-checkerboard-ptracer.xml -o references/tex-checkerboard-ptracer.pfm
