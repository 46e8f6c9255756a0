# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 44 s
mitsuba -q -p 1 -Dspp=4096 scenes/film-mitchell-border-ptracer.xml -o references/film-mitchell-border-ptracer.pfm
