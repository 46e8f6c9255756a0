"""Orientation: which way a surface faces, from its winding or its vertex normals
(faceNormals, flipNormals), one-sided BSDFs seen from behind, and twosided."""
from tools.conformance.scene_groups.pieces import (DIFFUSE, ROOM_LIGHT, DEFAULT_RADIANCE, scene,
                                                   sphere, rect, obj, WHITE, PANEL)


def add_scenes(s):
    """Adds the group's scenes to `s` (name -> (convention, xml, integrators))."""
    pt_bdpt = ["pt", "bdpt"]
    s["orient-obj-emitter"] = ("OBJ emitter oriented by its vertex normals (down), not its winding (up)",
        scene("", light=obj("lamp_normals_down.obj", DIFFUSE % "0",
                            '<scale x="0.3" z="0.3"/><translate y="1.98"/>',
                            "") .replace("</shape>", "<emitter type=\"area\">%s</emitter>\n  </shape>" % DEFAULT_RADIANCE)
              + sphere(WHITE)), pt_bdpt + ["mlt"])
    s["orient-facenormals"] = ("faceNormals: the same lamp oriented by its winding (emits up)",
        scene("", light=obj("lamp_normals_down.obj", DIFFUSE % "0",
                            '<scale x="0.3" z="0.3"/><translate y="1.7"/>',
                            '    <boolean name="faceNormals" value="true"/>\n')
              .replace("</shape>", "<emitter type=\"area\">%s</emitter>\n  </shape>" % DEFAULT_RADIANCE)
              + sphere(WHITE)), pt_bdpt)
    s["orient-flipnormals"] = ("flipNormals on a rectangle emitter (faces down) and on an OBJ with normals",
        scene(obj("panel_normals_back.obj", '<bsdf type="diffuse"/>', PANEL,
                  '    <boolean name="flipNormals" value="true"/>\n'),
              light=ROOM_LIGHT.replace('<rotate x="1" angle="90"/>', '<rotate x="1" angle="-90"/>')
              .replace("</emitter>", "</emitter>\n    <boolean name=\"flipNormals\" value=\"true\"/>")
              % DEFAULT_RADIANCE), pt_bdpt)
    s["orient-onesided-back"] = ("a one-sided diffuse panel seen from its back is black",
        scene(rect(DIFFUSE % "0.8, 0.8, 0.8", '<scale x="0.6" y="0.6"/><rotate y="1" angle="180"/>'
                   '<translate y="0.8" z="-0.2"/>')), pt_bdpt)
    s["orient-twosided"] = ("twosided makes the back of a panel reflect like its front",
        scene(rect('<bsdf type="twosided">' + DIFFUSE % "0.8, 0.8, 0.8" + "</bsdf>",
                   '<scale x="0.6" y="0.6"/><rotate y="1" angle="180"/><translate y="0.8" z="-0.2"/>')),
        pt_bdpt)
    s["orient-obj-normals-back"] = ("an OBJ panel whose vertex normals face away is its back side",
        scene(obj("panel_normals_back.obj", DIFFUSE % "0.8, 0.8, 0.8", PANEL)), pt_bdpt)
