# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 85 s
mitsuba -q -p 2 -Dspp=1024 scenes/bsdf-roughconductor-grazing.xml -o references/bsdf-roughconductor-grazing.pfm
