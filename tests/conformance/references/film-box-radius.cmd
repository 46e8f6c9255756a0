# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 38 s
mitsuba -q -p 2 -Dspp=4096 scenes/film-box-radius.xml -o references/film-box-radius.pfm
