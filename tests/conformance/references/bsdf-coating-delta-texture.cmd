# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 25 s
mitsuba -q -p 2 -Dspp=2048 scenes/bsdf-coating-delta-texture.xml -o references/bsdf-coating-delta-texture.pfm
