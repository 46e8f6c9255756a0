# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 54 s
mitsuba -q -p 2 -Dspp=4096 scenes/bsdf-specular-tint-texture.xml -o references/bsdf-specular-tint-texture.pfm
