"""Shading normals: strictNormals true and false."""
from tools.conformance.scene_groups.pieces import DIFFUSE, integrator, scene, obj


def add_scenes(s):
    """Adds the group's scenes to `s` (name -> (convention, xml, integrators))."""
    pt_bdpt = ["pt", "bdpt"]
    # A level panel above the floor whose vertex normals lean 60 degrees towards the green
    # wall. strictNormals true drops the directions that the geometric and the shading
    # normal put on different sides; false lets the shading normal alone decide,
    # so the panel also gathers light from below it (a leak). On a closed convex mesh the two
    # agree: such directions end inside the mesh, or the one-sided BSDF turns them away.
    leaning = obj("panel_normals_lean.obj", DIFFUSE % "0.8, 0.8, 0.8",
                  '<scale value="0.55"/><rotate x="1" angle="-90"/><translate y="0.45" z="0.1"/>')
    s["normals-strict"] = ("strictNormals true: no light through a panel's leaning shading normals",
                           scene(leaning, integ=integrator(strict_normals=True)), pt_bdpt + ["mlt"])
    s["normals-loose"] = ("strictNormals false (Mitsuba's default): the shading normal decides",
                          scene(leaning, integ=integrator(strict_normals=False)), pt_bdpt + ["mlt"])
