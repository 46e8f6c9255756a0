# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 13 s
mitsuba -q -p 2 -Dspp=4096 scenes/pbrt-materials.xml -o references/pbrt-materials.pfm
