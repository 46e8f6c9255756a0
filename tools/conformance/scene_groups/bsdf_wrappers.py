"""The BSDFs that wrap a nested one: mask (with a bitmap's channels as its opacity), bumpmap,
coating and roughcoating (Mitsuba's own model, not a layered simulation) and normalmap;
and the default BSDF of a shape that names none."""
from tools.conformance.scene_groups.pieces import (DIFFUSE, scene, point, sphere, rect, PANEL,
                                                   TEXTURED, bitmap)


def add_scenes(s):
    """Adds the group's scenes to `s` (name -> (convention, xml, integrators))."""
    pt_bdpt = ["pt", "bdpt"]
    s["bsdf-mask"] = ("mask: opacity from a bitmap",
                      scene(rect('<bsdf type="mask"><texture type="bitmap" name="opacity">' + bitmap("holes.png") +
                                 '</texture>' + DIFFUSE % "0.8, 0.8, 0.3" + "</bsdf>", PANEL)), pt_bdpt)
    s["tex-channel-alpha"] = ("mask opacity from an RGBA PNG's alpha (bitmap channel a, linear)",
                              scene(rect('<bsdf type="mask"><texture type="bitmap" name="opacity">' +
                                         bitmap("grid-alpha.png", '<string name="channel" value="a"/>') +
                                         '</texture>' + DIFFUSE % "0.8, 0.8, 0.3" + "</bsdf>", PANEL)), ["pt"])
    s["tex-channel-g"] = ("bitmap channel g: the green channel, sRGB-decoded, as a grey texture",
                          scene(rect(TEXTURED % bitmap("grid-alpha.png", '<string name="channel" value="g"/>'),
                                     PANEL)), ["pt"])
    s["bsdf-bumpmap"] = ("bumpmap: a bitmap height field scaled by a scale texture",
                         scene(rect('<bsdf type="bumpmap"><texture type="scale"><float name="scale" value="0.02"/>'
                                    '<texture type="bitmap">' + bitmap("bumps.png") + '</texture></texture>' +
                                    DIFFUSE % "0.8, 0.8, 0.8" + "</bsdf>",
                                    '<scale x="0.9" y="0.9"/><rotate x="1" angle="-90"/><translate y="0.01"/>')), pt_bdpt)

    # Coatings (Mitsuba's own model, not a layered simulation) and the normal map.
    coated_diffuse = ('<bsdf type="coating"><float name="intIOR" value="1.7"/><float name="thickness" value="0.5"/>'
                      '<rgb name="sigmaA" value="0.2, 0.6, 1.2"/>' + DIFFUSE % "0.8, 0.75, 0.6" + '</bsdf>')
    coated_metal = ('<bsdf type="coating"><string name="intIOR" value="water"/><rgb name="specularReflectance" value="0.8"/>'
                    '<bsdf type="roughconductor"><string name="material" value="Au"/><string name="distribution" value="ggx"/>'
                    '<float name="alpha" value="0.2"/></bsdf></bsdf>')
    s["bsdf-coating"] = ("coating: intIOR 1.7, thickness 0.5, sigmaA over a diffuse; water over a rough gold (ggx 0.2)",
        scene(sphere(coated_diffuse, "-0.45, 0.38, 0.1", 0.38) + sphere(coated_metal, "0.45, 0.38, 0", 0.38)),
        pt_bdpt + ["mlt"])
    s["bsdf-coating-delta-texture"] = ("coating over a smooth conductor (a delta under the delta); a checkerboard sigmaA over a diffuse panel",
        scene(sphere('<bsdf type="coating"><float name="intIOR" value="1.4"/>'
                     '<bsdf type="conductor"><string name="material" value="Cu"/></bsdf></bsdf>', "0.45, 0.3, 0.2", 0.3) +
              rect('<bsdf type="coating"><float name="thickness" value="2"/>'
                   '<texture type="checkerboard" name="sigmaA"><rgb name="color0" value="0.05, 0.1, 0.2"/>'
                   '<rgb name="color1" value="0.6, 0.3, 0.05"/><float name="uscale" value="3"/><float name="vscale" value="3"/></texture>' +
                   DIFFUSE % "0.7, 0.7, 0.7" + '</bsdf>',
                   '<scale x="0.45" y="0.45"/><rotate y="1" angle="25"/><translate x="-0.35" y="0.8" z="-0.3"/>')),
        pt_bdpt)
    s["bsdf-roughcoating"] = ("roughcoating: ggx alpha 0.15 over a diffuse; beckmann alpha 0.3, thickness 2, sigmaA over a rough copper",
        scene(sphere('<bsdf type="roughcoating"><string name="distribution" value="ggx"/><float name="alpha" value="0.15"/>' +
                     DIFFUSE % "0.2, 0.5, 0.8" + '</bsdf>', "-0.45, 0.38, 0.1", 0.38) +
              sphere('<bsdf type="roughcoating"><float name="alpha" value="0.3"/><float name="intIOR" value="1.6"/>'
                     '<float name="thickness" value="2"/><rgb name="sigmaA" value="0.05, 0.2, 0.4"/>'
                     '<bsdf type="roughconductor"><string name="material" value="Cu"/><float name="alpha" value="0.1"/></bsdf></bsdf>',
                     "0.45, 0.38, 0", 0.38)),
        pt_bdpt + ["mlt"])
    s["bsdf-roughcoating-alpha-texture"] = ("roughcoating, ggx with a checkerboard alpha (0.03 and 0.4) over a diffuse panel; beckmann over a smooth conductor (Mitsuba weighs a nested delta by its sampling weight alone)",
        scene(rect('<bsdf type="roughcoating"><string name="distribution" value="ggx"/>'
                   '<texture type="checkerboard" name="alpha"><spectrum name="color0" value="0.03"/><spectrum name="color1" value="0.4"/>'
                   '<float name="uscale" value="3"/><float name="vscale" value="3"/></texture>' +
                   DIFFUSE % "0.75, 0.45, 0.25" + '</bsdf>',
                   '<scale x="0.45" y="0.45"/><rotate y="1" angle="25"/><rotate x="1" angle="-30"/><translate x="-0.35" y="0.7" z="-0.3"/>') +
              sphere('<bsdf type="roughcoating"><float name="alpha" value="0.2"/>'
                     '<bsdf type="conductor"><string name="material" value="Ag"/></bsdf></bsdf>', "0.45, 0.3, 0.2", 0.3)),
        pt_bdpt)
    s["bsdf-normalmap"] = ("normalmap: a gamma-1 bitmap of tangent-space normals over a rough plastic, on a panel lit from above",
        scene(rect('<bsdf type="normalmap"><texture type="bitmap">' + bitmap("normals.png", '<float name="gamma" value="1"/>') +
                   '</texture><bsdf type="roughplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.2"/>'
                   '<rgb name="diffuseReflectance" value="0.3, 0.5, 0.7"/></bsdf></bsdf>',
                   '<scale x="0.7" y="0.7"/><rotate x="1" angle="-25"/><translate y="0.75" z="-0.3"/>')),
        pt_bdpt)

    s["bsdf-default"] = ("shapes naming no BSDF: a one-sided diffuse 0.5, black on an emitter",
                         scene('  <shape type="sphere">\n    ' + point("center", "-0.45, 0.35, 0.1") +
                               '<float name="radius" value="0.35"/>\n  </shape>\n' +
                               '  <shape type="rectangle">\n    <transform name="toWorld"><scale x="0.3" y="0.4"/>'
                               '<rotate y="1" angle="160"/><translate x="0.45" y="0.6" z="-0.2"/></transform>\n  </shape>\n' +
                               '  <shape type="rectangle">\n    <transform name="toWorld"><scale x="0.5" y="0.3"/>'
                               '<translate y="1.2" z="-0.98"/></transform>\n    <emitter type="area">'
                               '<rgb name="radiance" value="2, 2.5, 3"/></emitter>\n  </shape>\n'), pt_bdpt)
