# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 3 s
mitsuba -q -p 2 -Dspp=4096 scenes/light-hide-emitters-env.xml -o references/light-hide-emitters-env.pfm
