# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 46 s
mitsuba -q -p 2 -Dspp=4096 scenes/depth-unbounded-ptracer.xml -o references/depth-unbounded-ptracer.pfm
