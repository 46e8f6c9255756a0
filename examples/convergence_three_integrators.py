#!/usr/bin/python3
"""MSE against samples (mutations) per pixel of pt, bdpt and mlt, rendered with `import emlt`.

    examples/convergence_three_integrators.py [SCENE] [OUT.png]   (after scripts/setup.sh)
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import emlt

scene = emlt.load(sys.argv[1] if len(sys.argv) > 1 else "scenes/cornell-box/scene.json")
size = dict(width=64, height=64, progress=False)
reference, _ = emlt.render(scene, "pt", spp=1024, seed=1, **size)
budgets = [1, 2, 4, 8, 16, 32]
for integrator, budget in [("pt", "spp"), ("bdpt", "spp"), ("mlt", "mpp")]:
    images = (emlt.render(scene, integrator, seed=2, **{budget: n}, **size)[0] for n in budgets)
    plt.loglog(budgets, [emlt.compare(reference, image)["mse"] for image in images], "o-",
               label=integrator)
plt.xlabel("samples (mlt: mutations) per pixel")
plt.ylabel("MSE against a 1024-spp pt reference")
plt.legend()
plt.savefig(sys.argv[2] if len(sys.argv) > 2 else "convergence.png", dpi=120)
