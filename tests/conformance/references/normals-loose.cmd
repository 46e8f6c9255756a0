# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 18 s
mitsuba -q -p 1 -Dspp=4096 scenes/normals-loose.xml -o references/normals-loose.pfm
