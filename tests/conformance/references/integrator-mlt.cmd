# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 12 s; scenes/.reference-integrator-mlt.xml is scenes/integrator-mlt.xml rendered by the integrator path
mitsuba -q -p 2 -Dspp=4096 scenes/.reference-integrator-mlt.xml -o references/integrator-mlt.pfm
