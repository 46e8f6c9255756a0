# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 109 s
mitsuba -q -p 1 -Dspp=4096 scenes/film-lanczos.xml -o references/film-lanczos.pfm
