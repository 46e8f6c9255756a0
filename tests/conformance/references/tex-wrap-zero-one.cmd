# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 9 s
mitsuba -q -p 1 -Dspp=4096 scenes/tex-wrap-zero-one.xml -o references/tex-wrap-zero-one.pfm
