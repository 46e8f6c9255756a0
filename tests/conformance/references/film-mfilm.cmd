# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 32 s
mitsuba -q -p 2 -Dspp=4096 scenes/film-mfilm.xml -o references/film-mfilm.pfm
