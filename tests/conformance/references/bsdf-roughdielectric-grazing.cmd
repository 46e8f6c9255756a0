# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 89 s
mitsuba -q -p 2 -Dspp=1024 scenes/bsdf-roughdielectric-grazing.xml -o references/bsdf-roughdielectric-grazing.pfm
