# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 17 s
mitsuba -q -p 2 -Dspp=4096 scenes/bsdf-roughplastic-nonlinear.xml -o references/bsdf-roughplastic-nonlinear.pfm
