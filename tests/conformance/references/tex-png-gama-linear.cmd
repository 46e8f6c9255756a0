# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 12 s
mitsuba -q -p 1 -Dspp=4096 scenes/tex-png-gama-linear.xml -o references/tex-png-gama-linear.pfm
