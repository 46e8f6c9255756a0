# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 50 s
mitsuba -q -p 2 -Dspp=4096 scenes/bsdf-dielectric-ptracer.xml -o references/bsdf-dielectric-ptracer.pfm
