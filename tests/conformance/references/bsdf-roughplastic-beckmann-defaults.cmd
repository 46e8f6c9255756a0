# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 24 s
mitsuba -q -p 2 -Dspp=1024 scenes/bsdf-roughplastic-beckmann-defaults.xml -o references/bsdf-roughplastic-beckmann-defaults.pfm
