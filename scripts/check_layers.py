#!/usr/bin/env python3
"""Checks that no engine file includes a file of a layer above its own.

The engine's folders follow the flow of a render, from the bottom up (LAYERS below): a file
may include files of its own layer and of the layers under it, never of one above, so that
each room can be read, tested and replaced without the ones that use it. A layer is a list of
glob patterns over the module paths (a header under include/emlt/ or a source under src/,
both without extension; mutations/ keeps its own prefix); the first layer whose pattern
matches a module is its layer, so a file that sits apart from its folder (the integrator
registry) is listed before the folder.

  scripts/check_layers.py [--root DIR]     exit 0 when clean, 1 with one line per violation
  scripts/check_layers.py --list           prints each module's layer
"""
import argparse
import fnmatch
import os
import re
import sys

LAYERS = [
    ("core", ["core/*"]),
    ("image", ["image/*"]),
    ("settings", ["settings/*"]),
    ("film", ["film/*"]),
    ("scene", ["scene/*", "scene/*/*"]),
    ("path", ["path/*"]),
    ("sampling", ["sampling/*"]),
    ("run", ["run/*"]),
    ("mcmc", ["mcmc/*"]),
    ("mutations", ["mutations/*", "mutations/*/*"]),
    ("integrators/registry", ["integrators/registry"]),  # listed before its folder: it sits on top
    ("integrators", ["integrators/*"]),
    ("integrators/mlt", ["integrators/mlt/*"]),
    ("integrators/pss", ["integrators/pss/*"]),
    ("integrators/erpt", ["integrators/erpt/*"]),  # its chains are path-space MLT's
    ("cli", ["cli/*"]),
]
# Rank of each layer: the registry names every integrator, so it ranks above all of them.
RANK = {name: i for i, (name, _) in enumerate(LAYERS)}
RANK["integrators/registry"] = RANK["integrators/erpt"] + 0.5

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def module_of(path):
    """The module of a file path relative to the root, or None outside the engine."""
    for prefix in ("include/emlt/", "src/"):
        if path.startswith(prefix):
            return os.path.splitext(path[len(prefix):])[0]
    if path.startswith("mutations/"):
        return os.path.splitext(path)[0]
    return None


def module_of_include(target):
    if target.startswith("emlt/"):
        return os.path.splitext(target[len("emlt/"):])[0]
    if target.startswith("src/") or target.startswith("mutations/"):
        return module_of(target)
    return None


def layer_of(module):
    for name, patterns in LAYERS:
        if any(fnmatch.fnmatchcase(module, p) and module.count("/") == p.count("/") for p in patterns):
            return name
    return None


def engine_files(root):
    for top in ("include/emlt", "src", "mutations"):
        for d, _, names in os.walk(os.path.join(root, top)):
            for n in sorted(names):
                if n.endswith((".h", ".cpp")):
                    yield os.path.relpath(os.path.join(d, n), root)


def check(root):
    problems = []
    for path in engine_files(root):
        module = module_of(path)
        layer = layer_of(module)
        if layer is None:
            problems.append(f"{path}: in no layer (add its folder to scripts/check_layers.py)")
            continue
        with open(os.path.join(root, path), encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                target = module_of_include(m.group(1))
                if target is None:
                    continue
                target_layer = layer_of(target)
                if target_layer is None:
                    problems.append(f"{path}:{number}: includes {m.group(1)}, in no layer")
                elif RANK[target_layer] > RANK[layer]:
                    problems.append(f"{path}:{number}: {layer} includes {m.group(1)} of {target_layer}, a layer above")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    parser.add_argument("--list", action="store_true", help="print each module's layer")
    args = parser.parse_args()
    root = os.path.abspath(args.root)
    if args.list:
        for path in engine_files(root):
            print(f"{layer_of(module_of(path)) or '-':22} {path}")
        return 0
    problems = check(root)
    for p in problems:
        print(p)
    if problems:
        print(f"check_layers: {len(problems)} include(s) against the layers", file=sys.stderr)
        return 1
    print(f"check_layers: {sum(1 for _ in engine_files(root))} files, no include runs up the layers")
    return 0


if __name__ == "__main__":
    sys.exit(main())
