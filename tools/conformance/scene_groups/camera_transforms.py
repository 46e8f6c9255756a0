"""Where things are: the camera's field of view along each fovAxis (non-square images, where
the axis matters) and its toWorld, and the transforms of shapes (translate, rotate, scale,
matrix, lookat and lookAt)."""
from tools.conformance.scene_groups.pieces import (DIFFUSE, sensor, scene, sphere, rect, WHITE,
                                                   TEXTURED, bitmap)


def add_scenes(s):
    """Adds the group's scenes to `s` (name -> (convention, xml, integrators))."""
    pt_bdpt = ["pt", "bdpt"]
    for axis in ("x", "y", "diagonal", "smaller", "larger"):
        s[f"camera-fovaxis-{axis}"] = (f"fovAxis {axis} on a 96x64 image",
                                       scene(sphere(WHITE), cam=sensor(96, 64, 40, axis)), pt_bdpt)
    s["camera-fovaxis-y-portrait"] = ("fovAxis smaller on a 48x80 portrait image",
                                      scene(sphere(WHITE), cam=sensor(48, 80, 40, "smaller")), pt_bdpt)
    s["camera-matrix"] = ("camera toWorld as rotate + translate (no lookat)",
                          scene(sphere(WHITE), cam=sensor(transform='<rotate y="1" angle="188"/><rotate x="1" angle="6"/>'
                                                                    '<translate x="-0.3" y="1.1" z="3.2"/>')), pt_bdpt)
    s["shape-transforms"] = ("scale, rotate, translate and matrix on shapes",
                             scene('  <shape type="cube">\n    <transform name="toWorld"><scale x="0.3" y="0.5" z="0.2"/>'
                                   '<rotate y="1" angle="30"/><translate x="-0.4" y="0.5"/></transform>\n    ' + WHITE +
                                   '\n  </shape>\n' +
                                   rect(DIFFUSE % "0.3, 0.6, 0.8",
                                        '<matrix value="0.3 0 0.1 0.45  0 0.4 0 0.5  -0.1 0 0.3 0.1  0 0 0 1"/>')), pt_bdpt)
    # Mitsuba's parser takes <lookAt> as well as <lookat>, and without `up` builds the frame
    # from its coordinateSystem() of the viewing direction: a textured panel shows the turn
    # about its normal, and a panel facing straight up has a frame where (0, 1, 0) has none.
    s["transform-lookAt"] = ("<lookAt> (camera, and panels without up) beside translate, rotate, scale and matrix",
                             scene(rect(TEXTURED % bitmap(), '<scale value="0.45"/><lookAt origin="-0.4, 0.85, -0.3" target="0.2, 1.1, 3"/>') +
                                   rect(DIFFUSE % "0.8, 0.5, 0.2", '<scale x="0.55" y="0.18"/><lookat origin="0.3, 0.02, 0.9" target="0.3, 3, 0.91"/>') +
                                   '  <shape type="cube">\n    <transform name="toWorld"><scale x="0.2" y="0.3" z="0.2"/>'
                                   '<rotate x="0.3" y="1" z="0.2" angle="35"/><translate x="0.5" y="0.3" z="-0.4"/></transform>\n    ' + WHITE +
                                   '\n  </shape>\n' +
                                   rect(DIFFUSE % "0.2, 0.4, 0.8", '<matrix value="0.25 0 0.1 0.3  0 0.3 0 1.2  -0.1 0 0.25 -0.6  0 0 0 1"/>'),
                                   cam=sensor(transform='<lookAt origin="0.2, 1.1, 3.3" target="0, 0.85, 0" up="0.1, 1, 0"/>')),
                             pt_bdpt)
