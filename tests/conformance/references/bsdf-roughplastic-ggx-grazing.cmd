# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 496 s
mitsuba -q -p 2 -Dspp=4096 scenes/bsdf-roughplastic-ggx-grazing.xml -o references/bsdf-roughplastic-ggx-grazing.pfm
