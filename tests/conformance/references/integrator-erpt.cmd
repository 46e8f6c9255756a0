# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 6 s; scenes/.reference-integrator-erpt.xml is scenes/integrator-erpt.xml rendered by the integrator path
mitsuba -q -p 2 -Dspp=4096 scenes/.reference-integrator-erpt.xml -o references/integrator-erpt.pfm
