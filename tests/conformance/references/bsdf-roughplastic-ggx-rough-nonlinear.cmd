# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 11 s
mitsuba -q -p 2 -Dspp=1024 scenes/bsdf-roughplastic-ggx-rough-nonlinear.xml -o references/bsdf-roughplastic-ggx-rough-nonlinear.pfm
