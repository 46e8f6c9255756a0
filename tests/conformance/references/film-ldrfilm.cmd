# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 23 s; scenes/.reference-film-ldrfilm.xml is scenes/film-ldrfilm.xml with its film made a hdrfilm writing PFM
mitsuba -q -p 2 -Dspp=4096 scenes/.reference-film-ldrfilm.xml -o references/film-ldrfilm.pfm
