# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 11 s
mitsuba -q -p 1 -Dspp=4096 scenes/tex-png-srgb-chunk.xml -o references/tex-png-srgb-chunk.pfm
