# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 10 s
mitsuba -q -p 1 -Dspp=4096 scenes/tex-gamma-15.xml -o references/tex-gamma-15.pfm
