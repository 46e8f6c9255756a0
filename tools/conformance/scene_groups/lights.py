"""Lights: an emissive sphere, the environment emitters (constant, envmap, sky, sun,
sunsky), hideEmitters, and the delta lights (point, spot, directional, collimated)."""
from tools.conformance.scene_groups.pieces import (DIFFUSE, integrator, scene, point, sphere, rect,
                                                   WHITE, bitmap)


def add_scenes(s):
    """Adds the group's scenes to `s` (name -> (convention, xml, integrators))."""
    pt_bdpt = ["pt", "bdpt"]
    s["light-sphere"] = ("an emissive sphere", scene(sphere(WHITE, "-0.3, 0.35, 0", 0.35),
                                                      light='  <shape type="sphere">\n    ' + point("center", "0.45, 1.3, 0") +
                                                            '<float name="radius" value="0.15"/>\n    <emitter type="area">'
                                                            '<rgb name="radiance" value="10, 8, 6"/></emitter>\n  </shape>\n'),
                         pt_bdpt)
    s["light-constant"] = ("constant environment emitter", scene(sphere(WHITE) + rect(WHITE, '<scale value="3"/><rotate x="1" angle="-90"/>'),
                                                                 light='  <emitter type="constant"><rgb name="radiance" value="0.8, 0.9, 1.2"/></emitter>\n',
                                                                 walls=False), pt_bdpt)
    # hideEmitters (Mitsuba's path tracer): the ceiling light, in view, is black, and so is
    # the sky seen past the room; what they light is not. emlt's other integrators leave
    # out the same one-segment paths, so all three are checked against Mitsuba's path image.
    s["light-hide-emitters"] = ("hideEmitters: an area light seen directly is black",
                          scene(sphere(WHITE), integ=integrator(hide_emitters=True)), pt_bdpt + ["mlt"])
    s["light-hide-emitters-env"] = ("hideEmitters: the sky seen directly is black",
                              scene(sphere(WHITE) + rect(WHITE, '<scale value="3"/><rotate x="1" angle="-90"/>'),
                                    light='  <emitter type="constant"><rgb name="radiance" value="0.8, 0.9, 1.2"/></emitter>\n',
                                    walls=False, integ=integrator(hide_emitters=True)), pt_bdpt + ["mlt"])
    s["light-envmap"] = ("envmap orientation (toWorld) and scale",
                         scene(sphere('<bsdf type="roughconductor"><string name="material" value="Al"/><float name="alpha" value="0.05"/></bsdf>') +
                               rect(WHITE, '<scale value="3"/><rotate x="1" angle="-90"/>'),
                               light='  <emitter type="envmap"><string name="filename" value="assets/sky.exr"/>'
                                     '<float name="scale" value="1.5"/><transform name="toWorld"><rotate y="1" angle="60"/></transform></emitter>\n',
                               walls=False), pt_bdpt)
    # An envmap's gamma replaces the map's curve, as a bitmap's does: a float map's values
    # are bent by it too (v^2.2 here).
    s["light-envmap-gamma"] = ("envmap gamma 2.2 over a float map (its values bent to v^2.2)",
                               scene(sphere(WHITE) + rect(WHITE, '<scale value="3"/><rotate x="1" angle="-90"/>'),
                                     light='  <emitter type="envmap"><string name="filename" value="assets/sky.exr"/>'
                                           '<float name="gamma" value="2.2"/></emitter>\n',
                                     walls=False), ["pt"])

    # Mitsuba's daylight emitters rasterise their radiance into a lat-long map for a nested
    # envmap; these check emlt's map of each (model, sun position, frame, scales). The sun
    # stays out of view: only its light, and the sky, are seen.
    floor = rect(WHITE, '<scale value="3"/><rotate x="1" angle="-90"/>')
    s["light-sky"] = ("sky: Hosek-Wilkie model, turbidity, albedo, stretch, explicit sunDirection",
                      scene(sphere('<bsdf type="roughconductor"><string name="material" value="Al"/><float name="alpha" value="0.05"/></bsdf>') + floor,
                            light='  <emitter type="sky"><float name="turbidity" value="4.5"/><rgb name="albedo" value="0.1, 0.4, 0.8"/>'
                                  '<float name="stretch" value="1.2"/><vector name="sunDirection" x="0.5" y="0.55" z="-0.4"/>'
                                  '<integer name="resolution" value="128"/><float name="scale" value="3"/></emitter>\n',
                            walls=False), pt_bdpt)
    s["light-sun"] = ("sun: Preetham solar disk (sunRadiusScale, turbidity), explicit sunDirection",
                      scene(sphere(WHITE, "-0.2, 0.45, 0", 0.45) + sphere(DIFFUSE % "0.8, 0.5, 0.2", "0.55, 0.2, 0.4", 0.2) + floor,
                            light='  <emitter type="sun"><vector name="sunDirection" x="-0.6" y="0.7" z="0.3"/>'
                                  '<float name="turbidity" value="5"/><float name="sunRadiusScale" value="4"/>'
                                  '<integer name="resolution" value="128"/><float name="scale" value="0.5"/></emitter>\n',
                            walls=False), pt_bdpt)
    s["light-sunsky"] = ("sunsky: sun position from latitude/longitude/date/time, toWorld, scale/skyScale/sunScale",
                         scene(sphere(WHITE, "-0.2, 0.45, 0", 0.45) + sphere(DIFFUSE % "0.2, 0.3, 0.8", "0.55, 0.2, 0.4", 0.2) + floor,
                               light='  <emitter type="sunsky"><float name="latitude" value="48.2"/><float name="longitude" value="16.37"/>'
                                     '<float name="timezone" value="1"/><integer name="year" value="2015"/><integer name="month" value="3"/>'
                                     '<integer name="day" value="21"/><float name="hour" value="10"/><float name="minute" value="45"/>'
                                     '<float name="turbidity" value="3.5"/><float name="scale" value="0.6"/><float name="skyScale" value="1.5"/>'
                                     '<transform name="toWorld"><rotate y="1" angle="-70"/></transform></emitter>\n',
                               walls=False), pt_bdpt)

    # Delta lights: no surface, found only by light sampling (never by a BSDF sample), never
    # seen from the camera. Each light stays out of view. The point and the directional light
    # go through every integrator (the path layer's delta vertices, each MCMC kernel).
    every_integrator = ["pt", "bdpt", "mlt", "gamlt", "emlt", "pssmlt", "mmlt"]
    point_light = ('  <emitter type="point"><point name="position" x="0.2" y="1.9" z="1.6"/>'
                   '<rgb name="intensity" value="3, 2.5, 2"/></emitter>\n')
    s["light-point"] = ("point light: intensity in W/sr, no cosine at the light, invisible",
                        scene(sphere(WHITE, "-0.3, 0.35, 0", 0.35) +
                              sphere(DIFFUSE % "0.8, 0.5, 0.2", "0.45, 0.25, -0.3", 0.25),
                              light=point_light), every_integrator)
    spot = ('  <emitter type="spot"><transform name="toWorld"><lookat origin="0.6, 1.9, 1.2" '
            'target="-0.2, 0, -0.3" up="0, 1, 0"/></transform><rgb name="intensity" value="9, 8, 6"/>'
            '<float name="cutoffAngle" value="28"/><float name="beamWidth" value="16"/>%s</emitter>\n')
    s["light-spot"] = ("spot light: cutoffAngle and beamWidth (falloff linear in angle), toWorld lookat",
                       scene(sphere(WHITE, "-0.3, 0.35, 0", 0.35), light=spot % ""),
                       pt_bdpt + ["mlt"])
    s["light-spot-texture"] = ("spot light projecting a bitmap texture over its cone",
                               scene(sphere(WHITE, "0.3, 0.3, -0.2", 0.3),
                                     light=spot % ('<texture type="bitmap" name="texture">%s</texture>'
                                                   % bitmap())), pt_bdpt)
    s["light-directional"] = ("directional light: irradiance at normal incidence, 'direction', shadows",
                              scene(sphere(WHITE, "-0.2, 0.45, 0", 0.45) +
                                    sphere(DIFFUSE % "0.2, 0.3, 0.8", "0.55, 0.2, 0.4", 0.2) + floor,
                                    light='  <emitter type="directional"><vector name="direction" '
                                          'x="0.5" y="-1" z="-0.35"/><rgb name="irradiance" '
                                          'value="2, 1.8, 1.5"/></emitter>\n',
                                    walls=False), every_integrator)
    s["light-sun-directional"] = ("sun with sunRadiusScale 0: a directional light of the sun disk's irradiance",
                                  scene(sphere(WHITE, "-0.2, 0.45, 0", 0.45) + floor,
                                        light='  <emitter type="sun"><vector name="sunDirection" x="-0.6" '
                                              'y="0.7" z="0.3"/><float name="turbidity" value="4"/>'
                                              '<float name="sunRadiusScale" value="0"/>'
                                              '<float name="scale" value="0.5"/></emitter>\n',
                                        walls=False), pt_bdpt)

    # A collimated beam: one point, one direction, rendered only by light tracing (Mitsuba's
    # path tracer draws nothing of it): against Mitsuba's ptracer, the beam hitting the back
    # of the sphere (the spot, a single bright point, out of view), which lights the room.
    s["light-collimated-ptracer"] = (
        "collimated beam: power along one ray, only light tracing renders it",
        scene(sphere(WHITE, "-0.3, 0.35, 0", 0.35),
              light='  <emitter type="collimated"><transform name="toWorld"><lookat origin="-0.3, 1.9, -0.9" '
                    'target="-0.3, 0.6, -0.25" up="0, 0, 1"/></transform><rgb name="power" value="6, 5, 4"/></emitter>\n',
              integ=integrator(kind="ptracer")),
        ["ptracer", "bdpt", "mlt"])
