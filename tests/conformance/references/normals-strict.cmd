# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 17 s
mitsuba -q -p 1 -Dspp=4096 scenes/normals-strict.xml -o references/normals-strict.pfm
