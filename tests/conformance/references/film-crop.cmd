# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 33 s
mitsuba -q -p 2 -Dspp=4096 scenes/film-crop.xml -o references/film-crop.pfm
