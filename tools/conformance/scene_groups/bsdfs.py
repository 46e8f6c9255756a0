"""The scattering BSDFs: smooth and rough dielectrics, conductors and plastics, their
textured tints and energy conservation, the classic analytic BRDFs (roughdiffuse, phong,
ward, difftrans), the weighted sums (mixturebsdf, blendbsdf), and the rough ones seen at
grazing angles."""
from tools.conformance.scene_groups.pieces import (DIFFUSE, ROOM_LIGHT, DEFAULT_RADIANCE, sensor,
                                                   scene, sphere, rect, obj, WHITE, bitmap)


def add_scenes(s):
    """Adds the group's scenes to `s` (name -> (convention, xml, integrators))."""
    pt_bdpt = ["pt", "bdpt"]
    bsdfs = {
        "bsdf-plastic": ("plastic", '<bsdf type="plastic"><rgb name="diffuseReflectance" value="0.6, 0.15, 0.1"/>'
                         '<float name="intIOR" value="1.5"/></bsdf>'),
        "bsdf-roughplastic": ("roughplastic, beckmann, nonlinear false",
                              '<bsdf type="roughplastic"><string name="distribution" value="beckmann"/>'
                              '<float name="alpha" value="0.2"/><rgb name="diffuseReflectance" value="0.1, 0.3, 0.6"/></bsdf>'),
        "bsdf-roughplastic-nonlinear": ("roughplastic, ggx, nonlinear true",
                                        '<bsdf type="roughplastic"><string name="distribution" value="ggx"/>'
                                        '<float name="alpha" value="0.3"/><boolean name="nonlinear" value="true"/>'
                                        '<rgb name="diffuseReflectance" value="0.1, 0.5, 0.2"/></bsdf>'),
        "bsdf-conductor-cu": ("conductor, named material Cu", '<bsdf type="conductor"><string name="material" value="Cu"/></bsdf>'),
        "bsdf-roughconductor-beckmann": ("roughconductor, beckmann, Au, alpha 0.2",
                                         '<bsdf type="roughconductor"><string name="material" value="Au"/>'
                                         '<float name="alpha" value="0.2"/></bsdf>'),
        "bsdf-roughconductor-ggx": ("roughconductor, ggx, Al, specularReflectance",
                                    '<bsdf type="roughconductor"><string name="distribution" value="ggx"/>'
                                    '<string name="material" value="Al"/><float name="alpha" value="0.3"/>'
                                    '<rgb name="specularReflectance" value="0.9, 0.8, 0.5"/></bsdf>'),
        "bsdf-roughconductor-phong": ("roughconductor, phong distribution",
                                      '<bsdf type="roughconductor"><string name="distribution" value="phong"/>'
                                      '<string name="material" value="Cu"/><float name="alpha" value="0.25"/></bsdf>'),
        "bsdf-roughconductor-aniso": ("roughconductor, ggx, alphaU and alphaV",
                                      '<bsdf type="roughconductor"><string name="distribution" value="ggx"/>'
                                      '<string name="material" value="Ag"/><float name="alphaU" value="0.05"/>'
                                      '<float name="alphaV" value="0.4"/></bsdf>'),
        "bsdf-dielectric": ("dielectric, intIOR 1.5", '<bsdf type="dielectric"><float name="intIOR" value="1.5"/></bsdf>'),
        "bsdf-roughdielectric": ("roughdielectric, beckmann alpha 0.15",
                                 '<bsdf type="roughdielectric"><float name="alpha" value="0.15"/>'
                                 '<string name="intIOR" value="bk7"/></bsdf>'),
        "bsdf-thindielectric": ("thindielectric", '<bsdf type="thindielectric"><float name="intIOR" value="1.5"/></bsdf>'),
    }
    bsdfs["bsdf-roughdielectric-aniso"] = ("roughdielectric, ggx, alphaU 0.08 and alphaV 0.35",
                                           '<bsdf type="roughdielectric"><string name="distribution" value="ggx"/>'
                                           '<float name="alphaU" value="0.08"/><float name="alphaV" value="0.35"/></bsdf>')
    bsdfs["bsdf-roughdielectric-phong"] = ("roughdielectric, phong, alpha 0.2",
                                           '<bsdf type="roughdielectric"><string name="distribution" value="phong"/>'
                                           '<float name="alpha" value="0.2"/></bsdf>')
    for name, (conv, bsdf) in bsdfs.items():
        s[name] = (conv, scene(sphere(bsdf)), pt_bdpt + (["mlt"] if name == "bsdf-dielectric" else []))
    # Textured specular tints of the dielectrics (Mitsuba reads numbers or textures): a
    # smooth and a rough glass sphere whose transmittance follows a checkerboard.
    tint = ('<texture type="checkerboard" name="specularTransmittance">'
            '<rgb name="color0" value="1, 0.6, 0.3"/><rgb name="color1" value="0.3, 0.6, 1"/>'
            '<float name="uscale" value="4"/><float name="vscale" value="2"/></texture>')
    s["bsdf-specular-tint-texture"] = (
        "checkerboard specularTransmittance of a dielectric and a roughdielectric",
        scene(sphere('<bsdf type="dielectric">' + tint + '</bsdf>', "-0.45, 0.4, 0", 0.4) +
              sphere('<bsdf type="roughdielectric"><float name="alpha" value="0.2"/>' + tint + '</bsdf>',
                     "0.45, 0.4, -0.1", 0.4)), ["pt"])
    # ensureEnergyConservation: reflectances above 1 scaled to 0.99 of their maximum, each
    # parameter on its own (a plastic's diffuse part here, not its specular one).
    s["bsdf-energy-conservation"] = (
        "reflectances above 1 scaled to 0.99 over their maximum (diffuse 1.6, plastic diffuse 1.3)",
        scene(sphere(DIFFUSE % "1.6, 0.8, 0.4", "-0.45, 0.4, 0", 0.4) +
              sphere('<bsdf type="plastic"><rgb name="diffuseReflectance" value="1.3, 1, 0.5"/></bsdf>',
                     "0.45, 0.4, -0.1", 0.4)), ["pt"])
    # The classic analytic BRDFs Mitsuba 0.6 ships beside the microfacet ones, on the sphere
    # (every pair of angles at once). Oren-Nayar is rough enough here to differ from a
    # Lambertian by 10-20 % in its brightest and darkest parts.
    classic = {
        "bsdf-roughdiffuse": ("roughdiffuse (Oren-Nayar, full model), alpha 0.7",
            '<bsdf type="roughdiffuse"><rgb name="reflectance" value="0.75, 0.5, 0.3"/>'
            '<float name="alpha" value="0.7"/></bsdf>'),
        "bsdf-roughdiffuse-fast": ("roughdiffuse, useFastApprox, alpha 0.9, reflectance named diffuseReflectance",
            '<bsdf type="roughdiffuse"><rgb name="diffuseReflectance" value="0.3, 0.6, 0.7"/>'
            '<float name="alpha" value="0.9"/><boolean name="useFastApprox" value="true"/></bsdf>'),
        "bsdf-roughdiffuse-texture": ("roughdiffuse, checkerboard alpha (0.05 and 1.2) and reflectance",
            '<bsdf type="roughdiffuse">'
            '<texture type="checkerboard" name="reflectance"><rgb name="color0" value="0.8, 0.7, 0.2"/>'
            '<rgb name="color1" value="0.2, 0.4, 0.8"/><float name="uscale" value="4"/><float name="vscale" value="2"/></texture>'
            '<texture type="checkerboard" name="alpha"><spectrum name="color0" value="0.05"/><spectrum name="color1" value="1.2"/>'
            '<float name="uscale" value="6"/><float name="vscale" value="3"/></texture></bsdf>'),
        "bsdf-phong": ("phong, exponent 40, specularReflectance and diffuseReflectance",
            '<bsdf type="phong"><float name="exponent" value="40"/><rgb name="specularReflectance" value="0.4, 0.35, 0.3"/>'
            '<rgb name="diffuseReflectance" value="0.2, 0.3, 0.5"/></bsdf>'),
        "bsdf-phong-defaults": ("phong defaults (exponent 30, specular 0.2, diffuse 0.5)", '<bsdf type="phong"/>'),
        "bsdf-phong-energy": ("phong whose reflectances sum above 1 (scaled to 0.99 of their largest sum)",
            '<bsdf type="phong"><float name="exponent" value="10"/><spectrum name="specularReflectance" value="0.6"/>'
            '<rgb name="diffuseReflectance" value="0.8, 0.5, 0.3"/></bsdf>'),
        "bsdf-phong-texture": ("phong, checkerboard exponent (5 and 200) and diffuseReflectance",
            '<bsdf type="phong">'
            '<texture type="checkerboard" name="exponent"><spectrum name="color0" value="5"/><spectrum name="color1" value="200"/>'
            '<float name="uscale" value="6"/><float name="vscale" value="3"/></texture>'
            '<texture type="checkerboard" name="diffuseReflectance"><rgb name="color0" value="0.6, 0.2, 0.1"/>'
            '<rgb name="color1" value="0.1, 0.3, 0.5"/><float name="uscale" value="4"/><float name="vscale" value="2"/></texture>'
            '<spectrum name="specularReflectance" value="0.3"/></bsdf>'),
        "bsdf-ward": ("ward, balanced (the default), alphaU 0.05 and alphaV 0.3 along the sphere's dp/du",
            '<bsdf type="ward"><float name="alphaU" value="0.05"/><float name="alphaV" value="0.3"/>'
            '<rgb name="specularReflectance" value="0.5, 0.45, 0.4"/><rgb name="diffuseReflectance" value="0.15, 0.2, 0.3"/></bsdf>'),
        "bsdf-ward-original": ("ward, variant ward (Ward's own normalisation), alpha 0.15",
            '<bsdf type="ward"><string name="variant" value="ward"/><float name="alpha" value="0.15"/>'
            '<spectrum name="specularReflectance" value="0.4"/><rgb name="diffuseReflectance" value="0.4, 0.2, 0.1"/></bsdf>'),
        "bsdf-ward-duer": ("ward, variant ward-duer, alpha 0.2, default reflectances",
            '<bsdf type="ward"><string name="variant" value="ward-duer"/><float name="alpha" value="0.2"/></bsdf>'),
        "bsdf-ward-texture": ("ward, checkerboard alphaU (0.03 and 0.4), alphaV from alpha 0.1, checkerboard diffuseReflectance",
            '<bsdf type="ward"><float name="alpha" value="0.1"/>'
            '<texture type="checkerboard" name="alphaU"><spectrum name="color0" value="0.03"/><spectrum name="color1" value="0.4"/>'
            '<float name="uscale" value="6"/><float name="vscale" value="3"/></texture>'
            '<texture type="checkerboard" name="diffuseReflectance"><rgb name="color0" value="0.5, 0.3, 0.1"/>'
            '<rgb name="color1" value="0.1, 0.2, 0.5"/><float name="uscale" value="4"/><float name="vscale" value="2"/></texture>'
            '<spectrum name="specularReflectance" value="0.35"/></bsdf>'),
        "bsdf-difftrans": ("difftrans: a sphere letting light through both its sides diffusely",
            '<bsdf type="difftrans"><rgb name="transmittance" value="0.8, 0.6, 0.3"/></bsdf>'),
    }
    for name, (conv, bsdf) in classic.items():
        s[name] = (conv, scene(sphere(bsdf)), pt_bdpt + ["mlt"])
    # A diffuser under the lamp: the room is lit only through it, and it is seen from below.
    s["bsdf-difftrans-diffuser"] = ("difftrans: a checkerboard diffuseTransmittance panel under the lamp lights the room",
        scene(sphere(WHITE) + rect('<bsdf type="difftrans"><texture type="checkerboard" name="diffuseTransmittance">'
                                   '<rgb name="color0" value="0.9, 0.8, 0.6"/><rgb name="color1" value="0.3, 0.5, 0.9"/>'
                                   '<float name="uscale" value="2"/><float name="vscale" value="2"/></texture></bsdf>',
                                   '<scale x="0.45" y="0.45"/><rotate x="1" angle="90"/><translate y="1.8"/>')),
        pt_bdpt + ["mlt"])
    # Weighted sums of BSDFs. The mixture's weights sum above 1 and are divided by their sum
    # (ensureEnergyConservation); the second sphere keeps its weights and mixes in a delta
    # lobe. The blend's weight is a number on the sphere and a bitmap's channel mean on the
    # panel, between a diffuse and a smooth gold mirror.
    gold = '<bsdf type="conductor"><string name="material" value="Au"/></bsdf>'
    s["bsdf-mixturebsdf"] = ("mixturebsdf: weights 0.6, 0.7 (scaled to sum 1) of diffuse and rough copper; "
                             "0.3; 0.5 of gold and diffuse without energy conservation",
        scene(sphere('<bsdf type="mixturebsdf"><string name="weights" value="0.6, 0.7"/>' +
                     DIFFUSE % "0.8, 0.3, 0.2" +
                     '<bsdf type="roughconductor"><string name="material" value="Cu"/>'
                     '<string name="distribution" value="ggx"/><float name="alpha" value="0.2"/></bsdf></bsdf>',
                     "-0.42, 0.4, 0", 0.4) +
              sphere('<bsdf type="mixturebsdf"><string name="weights" value="0.3; 0.5"/>'
                     '<boolean name="ensureEnergyConservation" value="false"/>' + gold +
                     DIFFUSE % "0.2, 0.5, 0.8" + '</bsdf>', "0.45, 0.35, 0.1", 0.35)),
        pt_bdpt + ["mlt"])
    s["bsdf-blendbsdf"] = ("blendbsdf: weight 0.3 between diffuse and rough plastic; a bitmap weight between diffuse and gold",
        scene(sphere('<bsdf type="blendbsdf"><float name="weight" value="0.3"/>' + DIFFUSE % "0.3, 0.7, 0.4" +
                     '<bsdf type="roughplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.1"/>'
                     '<rgb name="diffuseReflectance" value="0.7, 0.2, 0.1"/></bsdf></bsdf>', "-0.45, 0.35, 0.1", 0.35) +
              rect('<bsdf type="blendbsdf"><texture type="bitmap" name="weight">' + bitmap() + '</texture>' +
                   DIFFUSE % "0.8, 0.8, 0.8" + gold + '</bsdf>',
                   '<scale x="0.4" y="0.4"/><rotate y="1" angle="-20"/><translate x="0.45" y="0.7" z="-0.3"/>')),
        pt_bdpt + ["mlt"])
    # Rough plastic seen and lit at grazing angles: a panel over the floor, a low camera.
    # Mitsuba weights the base by the rough coating's transmittance, which at grazing
    # angles is far above the smooth 1 - F (GGX alpha 0.12: 0.64 against 0.43 at cos 0.1).
    low_camera = sensor(96, 48, 45, transform='<lookat origin="0, 0.3, 2.4" target="0, 0.12, -1" up="0, 1, 0"/>')
    # A low lamp behind the camera lights the panel at grazing angles too.
    grazing_light = ('  <shape type="rectangle">\n    <transform name="toWorld"><scale x="0.4" y="0.12"/>'
                     '<rotate y="1" angle="180"/><translate y="0.14" z="2.6"/></transform>\n'
                     '    <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>\n'
                     '    <emitter type="area"><rgb name="radiance" value="30, 27, 22"/></emitter>\n  </shape>\n')
    floor_panel = '<scale value="0.99"/><rotate x="1" angle="-90"/><translate y="0.005"/>'
    rough_floors = {
        "bsdf-roughplastic-ggx-grazing": ("roughplastic, ggx alpha 0.12, intIOR 1.5, at grazing angles",
            '<bsdf type="roughplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.12"/>'
            '<float name="intIOR" value="1.5"/><rgb name="diffuseReflectance" value="0.55, 0.45, 0.3"/></bsdf>'),
        "bsdf-roughplastic-ggx-rough-nonlinear": ("roughplastic, ggx alpha 0.5, nonlinear true, at grazing angles",
            '<bsdf type="roughplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.5"/>'
            '<boolean name="nonlinear" value="true"/><rgb name="diffuseReflectance" value="0.2, 0.5, 0.7"/></bsdf>'),
        "bsdf-roughplastic-beckmann-defaults": ("roughplastic defaults (beckmann alpha 0.1, polypropylene, diffuse 0.5), at grazing angles",
            '<bsdf type="roughplastic"/>'),
        "bsdf-roughplastic-alpha-texture": ("roughplastic, ggx with a checkerboard alpha (0.02 and 0.3), at grazing angles",
            '<bsdf type="roughplastic"><string name="distribution" value="ggx"/>'
            '<texture type="checkerboard" name="alpha"><spectrum name="color0" value="0.02"/><spectrum name="color1" value="0.3"/>'
            '<float name="uscale" value="3"/><float name="vscale" value="3"/></texture>'
            '<rgb name="diffuseReflectance" value="0.6, 0.3, 0.2"/></bsdf>'),
        # The same view of the rough conductor and of a rough dielectric interface over the
        # diffuse floor: Mitsuba evaluates both without tables (a measurement, that they
        # have no such difference).
        "bsdf-roughconductor-grazing": ("roughconductor, ggx alpha 0.12, Cu, at grazing angles",
            '<bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha" value="0.12"/>'
            '<string name="material" value="Cu"/></bsdf>'),
        "bsdf-roughdielectric-grazing": ("roughdielectric, ggx alpha 0.12, intIOR 1.5, over a diffuse floor at grazing angles",
            '<bsdf type="roughdielectric"><string name="distribution" value="ggx"/><float name="alpha" value="0.12"/>'
            '<float name="intIOR" value="1.5"/></bsdf>'),
    }
    for name, (conv, bsdf) in rough_floors.items():
        s[name] = (conv, scene(rect(bsdf, floor_panel), light=ROOM_LIGHT % DEFAULT_RADIANCE + grazing_light,
                               cam=low_camera), pt_bdpt)
    # Anisotropy on a mesh follows dp/du of its uvs (turned 30 degrees off the panel's edges).
    s["bsdf-roughconductor-aniso-mesh"] = ("roughconductor, beckmann, alphaU 0.05 and alphaV 0.3 on an OBJ with uvs",
        scene(obj("panel_uv.obj", '<bsdf type="roughconductor"><string name="material" value="Cr"/>'
                  '<float name="alphaU" value="0.05"/><float name="alphaV" value="0.3"/></bsdf>',
                  '<rotate z="1" angle="30"/><scale x="0.6" y="0.6"/><rotate x="1" angle="-60"/>'
                  '<translate y="0.6" z="-0.2"/>')), pt_bdpt)
