"""Shapes: sphere, disk, cube, cylinder, serialized and PLY meshes, shapegroup and instance."""
from tools.conformance.scene_groups.pieces import DIFFUSE, scene, point, sphere, WHITE


def add_scenes(s):
    """Adds the group's scenes to `s` (name -> (convention, xml, integrators))."""
    pt_bdpt = ["pt", "bdpt"]
    s["shape-sphere-disk-cube"] = ("sphere, disk and cube",
                                   scene(sphere(WHITE, "-0.5, 0.3, 0", 0.3) +
                                         '  <shape type="disk">\n    <transform name="toWorld"><scale value="0.3"/>'
                                         '<rotate y="1" angle="20"/><translate x="0.45" y="0.8" z="-0.5"/></transform>\n    ' +
                                         DIFFUSE % "0.8, 0.4, 0.2" + '\n  </shape>\n' +
                                         '  <shape type="cube">\n    <transform name="toWorld"><scale value="0.2"/>'
                                         '<translate x="0.4" y="0.2" z="0.2"/></transform>\n    ' + WHITE + '\n  </shape>\n'),
                                   pt_bdpt)
    s["shape-cylinder"] = ("cylinder (open, p0/p1/radius)",
                           scene('  <shape type="cylinder">\n    ' + point("p0", "0, 0.1, 0") + point("p1", "0.2, 1.1, -0.1") +
                                 '<float name="radius" value="0.3"/>\n    ' +
                                 '<bsdf type="twosided">' + DIFFUSE % "0.8, 0.6, 0.3" + '</bsdf>\n  </shape>\n'), pt_bdpt)
    s["shape-serialized"] = ("serialized meshes chosen by shapeIndex",
                             scene('  <shape type="serialized">\n    <string name="filename" value="assets/shapes.serialized"/>'
                                   '<integer name="shapeIndex" value="1"/>\n    <transform name="toWorld"><scale value="0.5"/>'
                                   '<translate y="0.5"/></transform>\n    ' + WHITE + '\n  </shape>\n'
                                   '  <shape type="serialized">\n    <string name="filename" value="assets/shapes.serialized"/>'
                                   '<integer name="shapeIndex" value="0"/>\n    <transform name="toWorld"><scale value="0.3"/>'
                                   '<translate x="0.6" y="1.2" z="-0.5"/></transform>\n    ' + DIFFUSE % "0.2, 0.4, 0.8" +
                                   '\n  </shape>\n'), pt_bdpt)
    s["shape-ply"] = ("PLY meshes, ASCII with normals and binary with quads",
                      scene('  <shape type="ply">\n    <string name="filename" value="assets/ball_ascii.ply"/>\n'
                            '    <transform name="toWorld"><scale value="0.35"/><translate x="-0.4" y="0.35"/></transform>\n    ' +
                            WHITE + '\n  </shape>\n'
                            '  <shape type="ply">\n    <string name="filename" value="assets/pyramid_binary.ply"/>\n'
                            '    <transform name="toWorld"><scale value="0.35"/><translate x="0.4"/></transform>\n    ' +
                            DIFFUSE % "0.8, 0.5, 0.2" + '\n  </shape>\n'), pt_bdpt)
    s["shape-instance"] = ("shapegroup and instance",
                           scene('  <shape type="shapegroup" id="pair">\n' + sphere(WHITE, "0, 0.2, 0", 0.2) +
                                 sphere(DIFFUSE % "0.2, 0.3, 0.8", "0.3, 0.15, 0.2", 0.15) + '  </shape>\n'
                                 '  <shape type="instance">\n    <ref id="pair"/>\n    <transform name="toWorld">'
                                 '<translate x="-0.5"/></transform>\n  </shape>\n'
                                 '  <shape type="instance">\n    <ref id="pair"/>\n    <transform name="toWorld">'
                                 '<rotate y="1" angle="90"/><scale value="1.3"/><translate x="0.4" z="-0.2"/></transform>\n'
                                 '  </shape>\n'), pt_bdpt)
