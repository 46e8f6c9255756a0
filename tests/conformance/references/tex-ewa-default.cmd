# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 18 s
mitsuba -q -p 2 -Dspp=4096 scenes/tex-ewa-default.xml -o references/tex-ewa-default.pfm
