# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 34 s
mitsuba -q -p 2 -Dspp=1024 scenes/bsdf-roughplastic-alpha-texture.xml -o references/bsdf-roughplastic-alpha-texture.pfm
