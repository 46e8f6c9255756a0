# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 15 s; scenes/.reference-integrator-pssmlt.xml is scenes/integrator-pssmlt.xml rendered by the integrator path
mitsuba -q -p 2 -Dspp=4096 scenes/.reference-integrator-pssmlt.xml -o references/integrator-pssmlt.pfm
