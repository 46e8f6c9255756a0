"""Spectra: the forms a colour takes in a file (one value, three, rgb, srgb hex, a
wavelength list, a blackbody)."""
from tools.conformance.scene_groups.pieces import ROOM_LIGHT, scene, sphere, WHITE


def add_scenes(s):
    """Adds the group's scenes to `s` (name -> (convention, xml, integrators))."""
    pt_bdpt = ["pt", "bdpt"]
    cbox_white = ("400:0.343, 404:0.445, 408:0.551, 412:0.624, 416:0.665, 420:0.687, 424:0.708, 428:0.723, "
                  "432:0.715, 436:0.71, 440:0.745, 444:0.758, 448:0.739, 452:0.767, 456:0.777, 460:0.765, "
                  "464:0.751, 468:0.745, 472:0.748, 476:0.729, 480:0.745, 484:0.757, 488:0.753, 492:0.75, "
                  "496:0.746, 500:0.747, 504:0.735, 508:0.732, 512:0.739, 516:0.734, 520:0.725, 524:0.721, "
                  "528:0.733, 532:0.725, 536:0.732, 540:0.743, 544:0.744, 548:0.748, 552:0.728, 556:0.716, "
                  "560:0.733, 564:0.726, 568:0.713, 572:0.74, 576:0.754, 580:0.764, 584:0.752, 588:0.736, "
                  "592:0.734, 596:0.741, 600:0.74, 604:0.732, 608:0.745, 612:0.755, 616:0.751, 620:0.744, "
                  "624:0.731, 628:0.733, 632:0.744, 636:0.731, 640:0.712, 644:0.708, 648:0.729, 652:0.73, "
                  "656:0.727, 660:0.707, 664:0.703, 668:0.729, 672:0.75, 676:0.76, 680:0.751, 684:0.739, "
                  "688:0.724, 692:0.73, 696:0.74, 700:0.737")
    cbox_light = "400:0, 500:8, 600:15.6, 700:18.4"
    s["spectrum-forms"] = ("one value, three values, rgb, srgb hex and a wavelength list as reflectances",
                           scene(sphere('<bsdf type="diffuse"><spectrum name="reflectance" value="%s"/></bsdf>' % cbox_white,
                                        center="-0.45, 0.3, 0", radius=0.3) +
                                 sphere('<bsdf type="diffuse"><spectrum name="reflectance" value="0.2, 0.5, 0.8"/></bsdf>',
                                        center="0.45, 0.3, 0", radius=0.3) +
                                 sphere('<bsdf type="diffuse"><srgb name="reflectance" value="#c08040"/></bsdf>',
                                        center="0, 0.3, 0.45", radius=0.3) +
                                 sphere('<bsdf type="diffuse"><spectrum name="reflectance" value="0.4"/></bsdf>',
                                        center="0, 0.9, -0.3", radius=0.3)), pt_bdpt)
    s["spectrum-emitter"] = ("an emitter's radiance as a wavelength list (the classic Cornell box's lamp)",
                             scene(sphere(WHITE), light=ROOM_LIGHT % ('<spectrum name="radiance" value="%s"/>' % cbox_light)),
                             pt_bdpt)
    s["spectrum-blackbody"] = ("an emitter's radiance as a blackbody with scale",
                               scene(sphere(WHITE), light=ROOM_LIGHT % '<blackbody name="radiance" temperature="3200K" scale="0.012"/>'),
                               pt_bdpt)
