"""The film's reconstruction filters: the default gaussian, and filters with negative lobes."""
from tools.conformance.scene_groups.pieces import sensor, scene, sphere, WHITE


def add_scenes(s):
    """Adds the group's scenes to `s` (name -> (convention, xml, integrators))."""
    pt_bdpt = ["pt", "bdpt"]
    s["film-gaussian"] = ("the film's default reconstruction filter (gaussian)",
                          scene(sphere(WHITE), cam=sensor(rfilter=None)), pt_bdpt + ["mlt"])
    # Filters with negative lobes, tabulated as Mitsuba tabulates them: the ceiling light seen
    # directly is an edge of about 30:1, which rings; the room fills the frame, so the border
    # pixels' renormalisation shows too.
    s["film-mitchell"] = ("mitchell filter, B 0.2 and C 0.6 (negative lobes)",
                          scene(sphere(WHITE), cam=sensor(rfilter="mitchell", rfilter_params=
                                '<float name="B" value="0.2"/><float name="C" value="0.6"/>')),
                          pt_bdpt + ["mlt"])
    s["film-catmullrom"] = ("catmullrom filter (negative lobes)",
                            scene(sphere(WHITE), cam=sensor(rfilter="catmullrom")), pt_bdpt + ["mlt"])
    s["film-lanczos"] = ("lanczos filter, 2 lobes (negative lobes)",
                         scene(sphere(WHITE), cam=sensor(rfilter="lanczos", rfilter_params=
                               '<integer name="lobes" value="2"/>')), pt_bdpt + ["mlt"])
