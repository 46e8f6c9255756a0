# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 36 s
mitsuba -q -p 2 -Dspp=4096 scenes/bsdf-energy-conservation.xml -o references/bsdf-energy-conservation.pfm
