# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 38 s; scenes/.reference-integrator-memlt-rough.xml is scenes/integrator-memlt-rough.xml rendered by the integrator path
mitsuba -q -p 2 -Dspp=16384 scenes/.reference-integrator-memlt-rough.xml -o references/integrator-memlt-rough.pfm
