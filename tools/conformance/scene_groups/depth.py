"""Path depth: maxDepth 1, 2, 3, 8 and -1, and rrDepth."""
from tools.conformance.scene_groups.pieces import integrator, scene, sphere, WHITE


def add_scenes(s):
    """Adds the group's scenes to `s` (name -> (convention, xml, integrators))."""
    pt_bdpt = ["pt", "bdpt"]
    for depth in (1, 2, 3, 8):
        s[f"depth-{depth}"] = (f"maxDepth {depth}", scene(sphere(WHITE), integ=integrator(max_depth=depth)),
                               pt_bdpt + ["mlt"])
    s["depth-unbounded"] = ("maxDepth -1 (Russian roulette from rrDepth 5)",
                            scene(sphere(WHITE), integ=integrator(max_depth=-1)), pt_bdpt + ["mlt"])
    s["depth-rr1"] = ("rrDepth 1 changes no expectation", scene(sphere(WHITE), integ=integrator(max_depth=-1, rr_depth=1)),
                      pt_bdpt + ["mlt"])
