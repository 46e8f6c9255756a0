# Mitsuba 0.6 (version 0.6.0, RGB mode, single precision), run in tests/conformance/, 49 s; scenes/.reference-film-tiledhdrfilm.xml is scenes/film-tiledhdrfilm.xml with its film made a hdrfilm writing PFM
mitsuba -q -p 2 -Dspp=4096 scenes/.reference-film-tiledhdrfilm.xml -o references/film-tiledhdrfilm.pfm
