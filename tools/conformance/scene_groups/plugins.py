"""The plugins no other group names: a thin lens, an orthographic camera, the tent and
gaussian filters, the direct, bdpt and Metropolis integrators, every sampler and every film."""
from tools.conformance.scene_groups.pieces import (DIFFUSE, HDR_PFM, sensor, integrator, scene,
                                                   sphere, rect, WHITE, TEXTURED, bitmap)


def add_scenes(s):
    """Scenes that name the plugins no other scene names: a thin lens, the tent and gaussian
    filters, the direct, bdpt and mlt integrators, every sampler and every film."""
    pt_bdpt = ["pt", "bdpt"]
    # Depth of field: the near sphere is in focus, the far one and the back wall are not.
    near_far = (sphere(WHITE, "-0.4, 0.3, 0.7", 0.3) + sphere(DIFFUSE % "0.8, 0.5, 0.2", "0.45, 0.4, -0.55", 0.4) +
                rect(TEXTURED % bitmap(), '<scale value="0.5"/><translate x="-0.2" y="1.2" z="-0.98"/>'))
    s["camera-thinlens"] = ("thinlens: apertureRadius 0.1, focusDistance 2.75 (near sphere sharp, back wall blurred)",
        scene(near_far, cam=sensor(kind="thinlens", params='\n    <float name="fov" value="50"/>'
                                   '\n    <float name="apertureRadius" value="0.1"/>'
                                   '\n    <float name="focusDistance" value="2.75"/>')),
        pt_bdpt + ["mlt"])
    # Mitsuba's tent has a fixed radius of one pixel (it reads no parameter).
    s["film-tent"] = ("tent filter (Mitsuba's fixed radius of 1 pixel)",
                      scene(sphere(WHITE), cam=sensor(rfilter="tent")), pt_bdpt)
    s["film-gaussian-stddev"] = ("a named gaussian filter, stddev 0.8 (radius 3.2 pixels)",
                                 scene(sphere(WHITE), cam=sensor(rfilter="gaussian",
                                       rfilter_params='<float name="stddev" value="0.8"/>')),
                                 pt_bdpt + ["mlt"])

    # Mitsuba's direct integrator: the emission seen by the camera (hideEmitters false) plus
    # one bounce of light, sampled from the lights and from the BSDF and combined by MIS;
    # rendered by emlt's `direct`, which means the same. A rough conductor makes the BSDF
    # samples matter; the walls add no indirect light.
    glossy = '<bsdf type="roughconductor"><string name="material" value="Au"/><float name="alpha" value="0.15"/></bsdf>'
    direct_subject = sphere(WHITE, "-0.4, 0.35, 0", 0.35) + sphere(glossy, "0.4, 0.35, -0.2", 0.35)
    s["integrator-direct"] = ("direct integrator: emitters seen directly, one bounce of MIS direct light",
        scene(direct_subject, integ='  <integrator type="direct">\n    <integer name="emitterSamples" value="2"/>'
                                    '\n    <integer name="bsdfSamples" value="2"/>\n  </integrator>\n'),
        ["direct"])
    # Mitsuba's own bidirectional path tracer and MLT make these references (maxDepth 4).
    bidir_subject = sphere(WHITE, "-0.4, 0.35, 0", 0.35) + sphere(glossy, "0.4, 0.35, -0.2", 0.35)
    s["integrator-bdpt"] = ("Mitsuba's bdpt, maxDepth 4, against emlt's bdpt",
                            scene(bidir_subject, integ=integrator(kind="bdpt", max_depth=4)), ["bdpt"])
    # Files naming Mitsuba's Metropolis integrators: their images converge to the path
    # tracer's, and Mitsuba's own MLT image is too noisy to be a reference (at 16,384
    # mutations per pixel emlt's mean agreed within 0.7 % but the per-pixel error was 5.6
    # times the renders' noise), so the reference is Mitsuba's path tracer on the same file
    # ("reference_integrator" in suite.json). The tuning parameters are read as notes.
    s["integrator-mlt"] = ("a file naming Mitsuba's mlt (maxDepth 4) renders with emlt's mlt; reference: Mitsuba's path tracer",
        scene(bidir_subject, integ='  <integrator type="mlt">\n    <integer name="maxDepth" value="4"/>'
                                   '\n    <integer name="luminanceSamples" value="50000"/>'
                                   '\n    <boolean name="manifoldPerturbation" value="false"/>\n  </integrator>\n'),
        ["mlt"])
    s["integrator-pssmlt"] = ("a file naming Mitsuba's pssmlt (maxDepth 4) renders with emlt's pssmlt; reference: Mitsuba's path tracer",
        scene(bidir_subject, integ='  <integrator type="pssmlt">\n    <integer name="maxDepth" value="4"/>'
                                   '\n    <boolean name="bidirectional" value="true"/>'
                                   '\n    <float name="pLarge" value="0.3"/>\n  </integrator>\n'),
        ["pssmlt"])
    # Mitsuba's ERPT: its image is the path tracer's (Cline et al.'s estimator is unbiased),
    # and its parameters (chains per pixel, their length, the direct light apart) are read.
    s["integrator-erpt"] = ("a file naming Mitsuba's erpt (maxDepth 4) renders with emlt's erpt; reference: Mitsuba's path tracer",
        scene(bidir_subject, integ='  <integrator type="erpt">\n    <integer name="maxDepth" value="4"/>'
                                   '\n    <float name="numChains" value="2"/>'
                                   '\n    <integer name="chainLength" value="50"/>'
                                   '\n    <integer name="directSamples" value="16"/>\n  </integrator>\n'),
        ["erpt"])

    # Mitsuba's mlt with the manifold perturbation is manifold exploration (emlt's memlt):
    # a glass sphere's caustic on the floor and the room seen through it make the chains
    # walk specular manifolds; its image is the path tracer's.
    glass = '<bsdf type="dielectric"><float name="intIOR" value="1.5"/></bsdf>'
    memlt = ('  <integrator type="mlt">\n    <integer name="maxDepth" value="5"/>'
             '\n    <integer name="luminanceSamples" value="50000"/>'
             '\n    <boolean name="manifoldPerturbation" value="true"/>'
             '\n    <float name="lambda" value="50"/>\n  </integrator>\n')
    s["integrator-memlt"] = ("a file naming Mitsuba's mlt with manifoldPerturbation (maxDepth 5) renders with emlt's memlt; reference: Mitsuba's path tracer",
        scene(sphere(glass, "-0.4, 0.35, 0", 0.35) + sphere(glossy, "0.4, 0.35, -0.2", 0.35), integ=memlt),
        ["memlt"])
    # The same with the glass ball rough (roughdielectric, alpha 0.05): the manifold
    # perturbation crosses it as specular about its microfacet normals (offset manifolds,
    # which Mitsuba's mlt always enables) far more often than it stops there.
    rough_glass = ('<bsdf type="roughdielectric"><float name="intIOR" value="1.5"/>'
                   '<float name="alpha" value="0.05"/></bsdf>')
    s["integrator-memlt-rough"] = ("Mitsuba's mlt with manifoldPerturbation through a rough glass ball (offset manifolds) renders with emlt's memlt; reference: Mitsuba's path tracer",
        scene(sphere(rough_glass, "-0.4, 0.35, 0", 0.35) + sphere(glossy, "0.4, 0.35, -0.2", 0.35), integ=memlt),
        ["memlt"])

    # Parallel projection: toWorld's scale sizes the film (x in [-1.1, 1.1], y over the
    # aspect's share of it); a view from above one corner shows two walls and the floor.
    # The path-space integrators see the film point as the projection of the first vertex.
    s["camera-orthographic"] = ("orthographic: parallel rays from toWorld's scaled film square",
        scene(sphere(WHITE, "-0.3, 0.35, 0", 0.35) + sphere(DIFFUSE % "0.8, 0.5, 0.2", "0.45, 0.25, 0.4", 0.25),
              cam=sensor(96, 64, kind="orthographic", params="",
                         transform='<scale x="1.1" y="1.1"/><lookat origin="1.2, 1.7, 3" target="0, 0.8, 0" up="0, 1, 0"/>')),
        ["pt", "bdpt", "mlt"])
    # Mitsuba's particle tracer reaches the orthographic film too (each vertex at its
    # projection, W_e 1/A); its image is the reference (the particle tracer's, above).
    s["camera-orthographic-ptracer"] = (
        "ptracer into an orthographic camera: each vertex splatted at its projection on the film",
        s["camera-orthographic"][1].replace('<integrator type="path">', '<integrator type="ptracer">'),
        ["ptracer"])

    # A sampler changes only the sequence of samples: each must give the same image.
    for kind in ("stratified", "halton", "hammersley", "ldsampler", "sobol"):
        s[f"sampler-{kind}"] = (f"{kind} sampler: the same image as the independent one",
                                scene(sphere(WHITE), cam=sensor(sampler=kind)), ["pt"])

    # Films. mfilm writes NumPy's format, which the reference script turns into a PFM: a
    # linear reference of the film itself. ldrfilm (tone-mapped 8-bit PNG) and tiledhdrfilm
    # (tiled OpenEXR) give none; their references are Mitsuba's hdrfilm images of the same
    # scene ("reference_film" in suite.json), so that they prove only what a film means
    # for the image's radiance: its width, height and reconstruction filter.
    s["film-mfilm"] = ("mfilm (NumPy, rgb): width, height and filter, a linear reference of its own",
                       scene(sphere(WHITE), cam=sensor(80, 48, 40, rfilter="tent", film="mfilm", film_params=
                             '\n      <string name="fileFormat" value="numpy"/>'
                             '\n      <string name="pixelFormat" value="rgb"/>')), ["pt"])
    s["film-ldrfilm"] = ("ldrfilm: width, height and filter against hdrfilm (emlt writes linear radiance)",
                         scene(sphere(WHITE), cam=sensor(48, 72, 40, rfilter="gaussian",
                               rfilter_params='<float name="stddev" value="0.3"/>', film="ldrfilm", film_params=
                               '\n      <string name="pixelFormat" value="rgb"/>')), ["pt"])
    s["film-tiledhdrfilm"] = ("tiledhdrfilm: width, height and filter against hdrfilm",
                              scene(sphere(WHITE), cam=sensor(96, 56, 45, rfilter="mitchell", film="tiledhdrfilm",
                                    film_params='\n      <string name="pixelFormat" value="rgb"/>')), ["pt"])
    # A crop window renders its part of the film alone, framed by the whole film (not
    # re-framed), and filters its border pixels as an image's (the default Gaussian).
    s["film-crop"] = ("crop window 64x40 at (20, 28) of a 96x72 film: the window alone, framed by the film",
                      scene(sphere(WHITE, "-0.3, 0.35, 0", 0.35) + sphere(DIFFUSE % "0.8, 0.5, 0.2", "0.45, 0.25, 0.4", 0.25),
                            cam=sensor(96, 72, 45, rfilter="gaussian", film_params=HDR_PFM +
                                       '\n      <integer name="cropOffsetX" value="20"/>'
                                       '\n      <integer name="cropOffsetY" value="28"/>'
                                       '\n      <integer name="cropWidth" value="64"/>'
                                       '\n      <integer name="cropHeight" value="40"/>')), pt_bdpt)
    # Mitsuba 0.6's box reads a radius: each sample counts for every pixel within it.
    s["film-box-radius"] = ("box filter of radius 1.5 (a sample counts for the pixels within 1.5 on each axis)",
                            scene(sphere(WHITE), cam=sensor(rfilter="box",
                                  rfilter_params='<float name="radius" value="1.5"/>')), pt_bdpt)
