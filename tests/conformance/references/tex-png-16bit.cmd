# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 11 s
mitsuba -q -p 1 -Dspp=4096 scenes/tex-png-16bit.xml -o references/tex-png-16bit.pfm
