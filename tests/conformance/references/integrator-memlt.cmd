# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 85 s; scenes/.reference-integrator-memlt.xml is scenes/integrator-memlt.xml rendered by the integrator path
mitsuba -q -p 2 -Dspp=16384 scenes/.reference-integrator-memlt.xml -o references/integrator-memlt.pfm
