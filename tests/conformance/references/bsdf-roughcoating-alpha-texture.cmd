# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 23 s
mitsuba -q -p 2 -Dspp=2048 scenes/bsdf-roughcoating-alpha-texture.xml -o references/bsdf-roughcoating-alpha-texture.pfm
