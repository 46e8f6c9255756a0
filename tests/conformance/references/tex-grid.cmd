# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 101 s
mitsuba -q -p 1 -Dspp=4096 scenes/tex-grid.xml -o references/tex-grid.pfm
