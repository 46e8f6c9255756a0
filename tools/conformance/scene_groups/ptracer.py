"""The particle tracer: scenes of the other groups with <integrator type="ptracer">, and
the filters' splats at the image's border."""
from tools.conformance.scene_groups.pieces import sensor, integrator, scene, sphere, WHITE


def add_scenes(s):
    """Adds the group's scenes to `s` (name -> (convention, xml, integrators))."""
    # Scenes of the groups before this one with <integrator type="ptracer">, whose
    # references are Mitsuba's ptracer images, not its path tracer's. They differ where a particle tracer
    # means something else: light reaching the camera only through a delta BSDF is black, and
    # a non-box filter's splats lose the part of the footprint that falls off the image. The
    # sky seen directly is drawn (Mitsuba's particles leave a sphere round the scene).
    ptracer = {
        "depth-3": "ptracer, maxDepth 3: lights seen directly, direct and one indirect bounce",
        "depth-unbounded": "ptracer, maxDepth -1 (Russian roulette from rrDepth 5)",
        "bsdf-roughconductor-ggx": "ptracer through a rough conductor (ggx)",
        "bsdf-roughdielectric": "ptracer through rough glass (adjoint refraction)",
        "bsdf-dielectric": "ptracer: smooth glass is black, its caustic is not",
        "tex-checkerboard": "ptracer on a textured panel",
        "light-sphere": "ptracer from an emissive sphere",
        "light-constant": "ptracer under a constant environment, the sky seen directly drawn",
        "light-envmap": "ptracer under an envmap (rotated, scaled), the sky seen directly drawn",
        "light-point": "ptracer from a point light",
        "light-directional": "ptracer from a directional light (rays from a disk covering the scene)",
    }
    for base, convention in ptracer.items():
        xml = s[base][1].replace('<integrator type="path">', '<integrator type="ptracer">')
        assert 'type="ptracer"' in xml, base
        s[base + "-ptracer"] = (convention, xml, ["ptracer"])
    # The room fills the frame, so that the border pixels, which lose the part of the
    # Gaussian footprint off the image, are lit.
    s["film-gaussian-border-ptracer"] = (
        "ptracer splats through the gaussian filter: border pixels keep only the footprint inside",
        scene(sphere(WHITE), cam=sensor(fov=28, rfilter=None), integ=integrator(kind="ptracer")),
        ["ptracer"])
    # The same through a filter with negative lobes: the splats carry the signed table.
    s["film-mitchell-border-ptracer"] = (
        "ptracer splats through a mitchell filter (B 0.2, C 0.6): signed weights, no renormalisation",
        scene(sphere(WHITE), cam=sensor(fov=28, rfilter="mitchell",
                                        rfilter_params='<float name="B" value="0.2"/><float name="C" value="0.6"/>'),
              integ=integrator(kind="ptracer")),
        ["ptracer"])
