# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 5 s
mitsuba -q -p 2 -Dspp=4096 scenes/tex-channel-g.xml -o references/tex-channel-g.pfm
