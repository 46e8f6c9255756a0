# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 12 s
mitsuba -q -p 1 -Dspp=4096 scenes/bsdf-roughconductor-aniso-mesh.xml -o references/bsdf-roughconductor-aniso-mesh.pfm
