"""Textures, mostly on a panel facing the camera: bitmaps (PNG, JPEG and EXR, their curves
and bit depths, uv transforms, wrap modes, filtering), checkerboard, gridtexture and
vertexcolors."""
from tools.conformance.scene_groups.pieces import (sensor, scene, sphere, rect, obj, PANEL,
                                                   TEXTURED, bitmap)


def add_scenes(s):
    """Adds the group's scenes to `s` (name -> (convention, xml, integrators))."""
    pt_bdpt = ["pt", "bdpt"]

    def panel_tex(params, file="grid.png"):
        return rect(TEXTURED % bitmap(file, params), PANEL)
    s["tex-png-srgb"] = ("an 8-bit PNG is sRGB-decoded", scene(panel_tex("")), pt_bdpt)
    s["tex-png-gamma"] = ("gamma 1 overrides a PNG's sRGB curve",
                          scene(panel_tex('<float name="gamma" value="1"/>')), pt_bdpt)
    s["tex-jpg-srgb"] = ("a JPEG is sRGB-decoded, its chroma upsampled as libjpeg does",
                         scene(panel_tex("", "grid.jpg")), pt_bdpt)
    s["tex-jpg-grey"] = ("a grey (progressive) JPEG gives three equal channels",
                         scene(panel_tex("", "grid-grey.jpg")), pt_bdpt)
    pt_only = ["pt"]  # the texels are the subject; one integrator reads them as any other
    s["tex-png-gama-linear"] = ("a PNG whose gAMA chunk says 1.0 is linear",
                                scene(panel_tex("", "grid-gama1.png")), pt_only)
    s["tex-png-gama-15"] = ("a PNG whose gAMA chunk says 1/1.5 is decoded as v^1.5",
                            scene(panel_tex("", "grid-gama15.png")), pt_only)
    s["tex-png-srgb-chunk"] = ("an sRGB chunk outranks a gAMA chunk",
                               scene(panel_tex("", "grid-srgb-gama15.png")), pt_only)
    s["tex-png-16bit"] = ("a 16-bit PNG keeps its 16-bit samples", scene(panel_tex("", "grid16.png")),
                          pt_only)
    s["tex-gamma-15"] = ("bitmap gamma 1.5 replaces the file's sRGB curve",
                         scene(panel_tex('<float name="gamma" value="1.5"/>')), pt_only)
    s["tex-exr-linear"] = ("an EXR texture is linear", scene(panel_tex("", "grid.exr")), pt_bdpt)
    s["tex-uv-transform"] = ("uscale/vscale and uoffset/voffset with repeat",
                             scene(panel_tex('<float name="uscale" value="3"/><float name="vscale" value="2"/>'
                                             '<float name="uoffset" value="0.25"/><float name="voffset" value="0.1"/>')),
                             pt_bdpt)
    s["tex-wrap-zero-one"] = ("uvscale 2 with wrapModeU zero and wrapModeV one",
                              scene(panel_tex('<float name="uvscale" value="2"/><string name="wrapModeU" value="zero"/>'
                                              '<string name="wrapModeV" value="one"/>')), pt_only)
    s["tex-wrap-clamp"] = ("uvscale 2 with wrapMode clamp",
                           scene(panel_tex('<float name="uvscale" value="2"/><string name="wrapMode" value="clamp"/>')),
                           pt_bdpt)
    s["tex-wrap-mirror"] = ("uvscale 2.5 with wrapMode mirror",
                            scene(panel_tex('<float name="uvscale" value="2.5"/><string name="wrapMode" value="mirror"/>')),
                            pt_bdpt)
    s["tex-obj-fliptexcoords"] = ("OBJ texture coordinates flipped by default, and not with flipTexCoords false",
                                  scene(obj("panel_uv.obj", TEXTURED % bitmap(),
                                            '<scale x="0.45" y="0.45"/><translate x="-0.5" y="0.8" z="-0.2"/>') +
                                        obj("panel_uv.obj", TEXTURED % bitmap(),
                                            '<scale x="0.45" y="0.45"/><translate x="0.5" y="0.8" z="-0.2"/>',
                                            '    <boolean name="flipTexCoords" value="false"/>\n')), pt_bdpt)
    s["tex-ewa-default"] = ("a bitmap with Mitsuba's default EWA filtering, minified on a receding floor",
                            scene(rect('<bsdf type="diffuse"><texture type="bitmap" name="reflectance">'
                                       '<string name="filename" value="assets/grid.png"/><float name="uvscale" value="6"/>'
                                       '</texture></bsdf>',
                                       '<scale value="0.98"/><rotate x="1" angle="-90"/><translate y="0.01"/>')), pt_bdpt)
    s["tex-checkerboard"] = ("checkerboard colours and uscale",
                             scene(rect('<bsdf type="diffuse"><texture type="checkerboard" name="reflectance">'
                                        '<rgb name="color0" value="0.1, 0.2, 0.7"/><rgb name="color1" value="0.8, 0.7, 0.1"/>'
                                        '<float name="uscale" value="4"/><float name="vscale" value="3"/></texture></bsdf>',
                                        PANEL)), pt_bdpt)
    # gridtexture (colours, lineWidth, uvscale, uoffset), and a checkerboard whose negative
    # uoffset puts u = 0 inside the panel: Mitsuba truncates the cell index towards zero, so
    # the two cells beside u = 0 share a colour.
    s["tex-grid"] = ("gridtexture, and a checkerboard across u = 0",
                     scene(rect('<bsdf type="diffuse"><texture type="gridtexture" name="reflectance">'
                                '<rgb name="color0" value="0.1, 0.3, 0.7"/><rgb name="color1" value="0.9, 0.8, 0.2"/>'
                                '<float name="lineWidth" value="0.08"/><float name="uvscale" value="3"/>'
                                '<float name="uoffset" value="0.3"/></texture></bsdf>',
                                '<scale x="0.45" y="0.45"/><translate x="-0.48" y="0.8" z="-0.2"/>') +
                           rect('<bsdf type="diffuse"><texture type="checkerboard" name="reflectance">'
                                '<rgb name="color0" value="0.1, 0.2, 0.7"/><rgb name="color1" value="0.8, 0.7, 0.1"/>'
                                '<float name="uscale" value="1.5"/><float name="uoffset" value="-0.75"/>'
                                '<float name="vscale" value="2"/></texture></bsdf>',
                                '<scale x="0.45" y="0.45"/><translate x="0.48" y="0.8" z="-0.2"/>')), pt_bdpt)
    vertex_colors = '<bsdf type="diffuse"><texture type="vertexcolors" name="reflectance"/></bsdf>'
    s["tex-vertexcolors"] = ("vertexcolors: PLY colours interpolated barycentrically; uchar / 255 "
                             "sRGB-decoded (binary), float as stored with srgb false (ASCII)",
                             scene('  <shape type="ply">\n    <string name="filename" value="assets/quad_colors_uchar.ply"/>\n'
                                   '    <transform name="toWorld"><scale x="0.45" y="0.6"/><translate x="-0.48" y="0.8" z="-0.2"/></transform>\n    ' +
                                   vertex_colors + '\n  </shape>\n'
                                   '  <shape type="ply">\n    <string name="filename" value="assets/quad_colors_float.ply"/>\n'
                                   '    <boolean name="srgb" value="false"/>\n'
                                   '    <transform name="toWorld"><scale x="0.45" y="0.6"/><translate x="0.48" y="0.8" z="-0.2"/></transform>\n    ' +
                                   vertex_colors + '\n  </shape>\n'), pt_bdpt)
    s["tex-sphere-uv"] = ("a bitmap on a sphere uses Mitsuba's sphere parametrisation",
                          scene(sphere(TEXTURED % bitmap()), cam=sensor()), pt_bdpt)
