#!/usr/bin/env python3
"""Lists every plugin of Mitsuba 0.6 and the parameters it reads, from Mitsuba's own source.

Run once, with a clone (or bare mirror) of github.com/mitsuba-renderer/mitsuba at hand:

    python3 -m tools.conformance.extract_mitsuba_plugins \
        --git-dir /path/to/mitsuba/.git > tools/conformance/mitsuba06_plugins.json

The output is committed (CI has neither network nor Mitsuba's source), and
tools/conformance/coverage_matrix.py asks emlt's loader about each entry of it. It records
facts only: each plugin's name, category and one-line title, and each parameter's name,
type and default. Where they come from:

- the plugins: the SConscript of each plugin directory (`SharedLibrary('name', [sources])`),
  so a plugin Mitsuba does not build (a commented-out line) is not listed;
- the parameters: the plugin's documentation (`\\parameter{names}{type}{... \\default{x}}` in
  its doc comment, the text Mitsuba's manual is made from), and then every
  `props.getFloat("name", default)`-style read in its sources and the local headers they
  include (microfacet.h reads `distribution` and `alpha` for every rough BSDF), for the
  parameters the documentation leaves out (`documented: false`);
- the base classes' parameters (an emitter's `samplingWeight`, a Monte Carlo integrator's
  `strictNormals`, a film's crop window ...): the reads in src/librender/ of the base class
  each plugin derives from (BASES below), added where the plugin's documentation does not
  already list them.
"""
import argparse
import json
import re
import subprocess
import sys

# Plugin directories, by the element a scene file writes them as.
CATEGORIES = [
    ("bsdf", "src/bsdfs"), ("emitter", "src/emitters"), ("sensor", "src/sensors"),
    ("film", "src/films"), ("rfilter", "src/rfilters"), ("texture", "src/textures"),
    ("shape", "src/shapes"), ("integrator", "src/integrators"), ("sampler", "src/samplers"),
    ("medium", "src/medium"), ("phase", "src/phase"), ("subsurface", "src/subsurface"),
    ("volume", "src/volume"),
]

# Base class -> (file in src/librender, the parameters its constructor reads). Which base a
# plugin has is read from its `class X : public Base` line; Sensor and the cameras inherit
# AbstractEmitter's toWorld, TriMesh is the base of the mesh shapes (faceNormals,
# flipNormals), Texture2D that of the uv-mapped textures.
BASES = {
    "Emitter": [("src/librender/emitter.cpp", ["toWorld", "samplingWeight"])],
    "Sensor": [("src/librender/emitter.cpp", ["toWorld"]),
               ("src/librender/sensor.cpp", ["shutterOpen", "shutterClose"])],
    "ProjectiveCamera": [("src/librender/emitter.cpp", ["toWorld"]),
                         ("src/librender/sensor.cpp",
                          ["shutterOpen", "shutterClose", "nearClip", "farClip",
                           "focusDistance"])],
    "PerspectiveCamera": [("src/librender/emitter.cpp", ["toWorld"]),
                          ("src/librender/sensor.cpp",
                           ["shutterOpen", "shutterClose", "nearClip", "farClip",
                            "focusDistance"])],
    "MonteCarloIntegrator": [("src/librender/integrator.cpp",
                              ["rrDepth", "maxDepth", "strictNormals", "hideEmitters"])],
    "Film": [("src/librender/film.cpp",
              ["width", "height", "cropOffsetX", "cropOffsetY", "cropWidth", "cropHeight",
               "highQualityEdges"])],
    "BSDF": [("src/librender/bsdf.cpp", ["ensureEnergyConservation"])],
    "TriMesh": [("src/librender/trimesh.cpp", ["faceNormals", "flipNormals"])],
    "Texture2D": [("src/librender/texture.cpp",
                   ["uoffset", "voffset", "uvscale", "uscale", "vscale"])],
}

# Documentation types (Mitsuba's LaTeX macros) -> the XML element a scene gives them as.
DOC_TYPES = {
    "Float": "float", "Integer": "integer", "Boolean": "boolean", "String": "string",
    "Spectrum": "spectrum", "Transform": "transform", "Point": "point", "Vector": "vector",
    "Texture": "texture",
}
# Documented entries that are nested objects, not parameters.
OBJECT_TYPES = {"BSDF", "Phase", "RFilter", "Volume", "Integrator", "Shape", "ShapeGroup",
                "Medium", "Emitter", "Sampler", "Film", "Sensor"}
# props.getX -> element name.
CODE_TYPES = {
    "getFloat": "float", "getInteger": "integer", "getSize": "integer", "getLong": "integer",
    "getBoolean": "boolean", "getString": "string", "getSpectrum": "spectrum",
    "getTransform": "transform", "getAnimatedTransform": "transform", "getPoint": "point",
    "getVector": "vector", "getPoint3": "point", "getVector3": "vector",
}


class Source:
    def __init__(self, git_dir):
        self.git_dir = git_dir

    def git(self, *args):
        return subprocess.run(["git", "--git-dir", self.git_dir, *args], check=True,
                              capture_output=True, text=True).stdout

    def show(self, path):
        return self.git("show", "HEAD:" + path)


def balanced(text, start):
    """The text inside the braces (or parentheses) opening at text[start], and the index past
    the closing one."""
    opening = text[start]
    closing = {"{": "}", "(": ")"}[opening]
    depth = 0
    for i in range(start, len(text)):
        if text[i] == opening:
            depth += 1
        elif text[i] == closing:
            depth -= 1
            if depth == 0:
                return text[start + 1:i], i + 1
    return text[start + 1:], len(text)


def plain(latex):
    """Documentation text without its LaTeX markup, on one line."""
    text = re.sub(r"^\s*\*", " ", latex, flags=re.M)
    text = re.sub(r"\\(?:showbreak|footnotesize|newline|small)\b", "", text)
    text = re.sub(r"\\(?:vspace|hspace)\{[^}]*\}", "", text)
    text = re.sub(r"\\(?:code|texttt|emph|textbf|mbox|pluginref|mathrm|text)\{([^}]*)\}", r"\1",
                  text)
    for markup, meant in (("\\showbreak", ""), ("\\_", "_"), ("\\&", "&"), ("$", "")):
        text = text.replace(markup, meant)
    text = re.sub(r"\\([A-Za-z]+)", r"\1", text)
    text = text.replace("{", "").replace("}", "")
    return " ".join(text.split())


def documented(text):
    """(title, [(names, types, default)]) from the plugin's doc comment."""
    match = re.search(r"\\plugin\{([^}]*)\}\{", text)
    title = ""
    if match:
        title = plain(balanced(text, match.end() - 1)[0])
    entries = []
    for match in re.finditer(r"\\parameter\{", text):
        names, pos = balanced(text, match.end() - 1)
        if pos >= len(text) or text[pos] != "{":
            continue
        types, pos = balanced(text, pos)
        body = balanced(text, pos)[0] if pos < len(text) and text[pos] == "{" else ""
        default = ""
        found = re.search(r"\\default\{", body)
        if found:
            default = plain(balanced(body, found.end() - 1)[0])
        names = [plain(n).replace(" ", "")
                 for n in re.sub(r"\\(?:showbreak|newline)", "", names).split(",")]
        types = [t for t in re.findall(r"\\([A-Za-z]+)", types) if t != "Or"]
        # "width, height" share one entry, and their defaults one text ("768, 576").
        parts = [d.strip() for d in default.split(",")]
        for i, name in enumerate(names):
            own = parts[i] if len(names) > 1 and len(parts) >= len(names) else default
            entries.append(([name], types, own))
    return title, entries


def code_reads(text):
    """[(name, element, default text)] for each props.getX("name"[, default]) in `text`."""
    reads = []
    for match in re.finditer(r"props\.(get\w+)\(", text):
        method = match.group(1)
        if method not in CODE_TYPES:
            continue
        args = balanced(text, match.end() - 1)[0]
        found = re.match(r'\s*"(\w+)"\s*(?:,\s*(.*))?$', args, re.S)
        if not found:
            continue  # a name computed at run time (a loop over "alpha" + suffix ...)
        default = " ".join((found.group(2) or "").split())
        reads.append((found.group(1), CODE_TYPES[method], default))
    return reads


def plugins_of(source, directory):
    """[(plugin, [source files])] from the directory's SConscript."""
    script = source.show(directory + "/SConscript")
    found = []
    for line in script.splitlines():
        if line.lstrip().startswith("#"):
            continue
        match = re.search(r"SharedLibrary\(\s*'(\w+)'\s*,\s*\[([^\]]*)\]", line)
        if not match:
            # A call spread over several lines (the bidirectional integrators).
            match = re.search(r"SharedLibrary\(\s*'(\w+)'\s*,\s*$", line)
            if not match:
                continue
        found.append(match.group(1))
    # Sources: read again over the whole text, calls may span lines.
    result = []
    for name in found:
        match = re.search(r"SharedLibrary\(\s*'" + name + r"'\s*,\s*\[([^\]]*)\]", script)
        files = re.findall(r"'([^']+\.cpp)'", match.group(1)) if match else []
        result.append((name, [directory + "/" + f for f in files]))
    return result


def with_local_headers(source, paths):
    """The sources and the headers beside them that they include ("microfacet.h")."""
    texts, seen = [], set()
    queue = list(paths)
    while queue:
        path = queue.pop(0)
        if path in seen:
            continue
        seen.add(path)
        try:
            text = source.show(path)
        except subprocess.CalledProcessError:
            continue
        texts.append(text)
        folder = path.rsplit("/", 1)[0]
        for header in re.findall(r'#include\s+"([\w/]+\.h)"', text):
            queue.append(folder + "/" + header)
    return texts


def base_parameters(source, bases):
    params = []
    for base in bases:
        for path, names in BASES.get(base, []):
            reads = {name: (kind, default) for name, kind, default in code_reads(source.show(path))}
            for name in names:
                kind, default = reads.get(name, ("", ""))
                params.append({"name": name, "type": kind, "default": "",
                               "code_default": default, "documented": False, "from": base})
    return params


def extract(source):
    commit = source.git("rev-parse", "HEAD").strip()
    categories = {}
    for category, directory in CATEGORIES:
        plugins = []
        for name, files in plugins_of(source, directory):
            texts = with_local_headers(source, files)
            main = texts[0] if texts else ""
            title, docs = documented(main)
            # What the code reads: the type Mitsuba parses a value as, and its default.
            reads = {}
            for text in texts:
                for n, kind, default in code_reads(text):
                    reads.setdefault(n, (kind, default))
            params, objects, seen = [], [], set()
            for names, types, default in docs:
                if names == ["Unnamed"] or (types and all(t in OBJECT_TYPES for t in types)):
                    objects.extend({"name": n, "types": types} for n in names if n != "Unnamed")
                    continue
                kinds = [DOC_TYPES[t] for t in types if t in DOC_TYPES]
                for n in names:
                    # The manual abbreviates a few families ("[lens, caustic]Perturbation",
                    # "sigmaT & albedo"); the code reads below list them by name.
                    if n in seen or not re.fullmatch(r"\w+", n):
                        continue
                    seen.add(n)
                    kind, code_default = reads.get(n, ("", ""))
                    types_here = ([kind] if kind else []) + [k for k in kinds if k != kind]
                    params.append({"name": n, "type": types_here[0] if types_here else "",
                                   "types": types_here, "default": default,
                                   "code_default": code_default, "documented": True})
            for n, (kind, default) in reads.items():
                if n in seen:
                    continue
                seen.add(n)
                params.append({"name": n, "type": kind, "types": [kind], "default": "",
                               "code_default": default, "documented": False})
            bases = set()
            for text in texts:
                bases.update(re.findall(r"class\s+\w+\s*:\s*public\s+(\w+)", text))
            for param in base_parameters(source, sorted(bases)):
                if param["name"] not in seen:
                    seen.add(param["name"])
                    param["types"] = [param["type"]]
                    params.append(param)
            plugins.append({"plugin": name, "description": title,
                            "sources": files, "parameters": params, "objects": objects})
        categories[category] = plugins
    return {"mitsuba": "https://github.com/mitsuba-renderer/mitsuba", "commit": commit,
            "generated_by": "python3 -m tools.conformance.extract_mitsuba_plugins",
            "categories": categories}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--git-dir", required=True, help="Mitsuba 0.6's git directory")
    args = parser.parse_args()
    json.dump(extract(Source(args.git_dir)), sys.stdout, indent=1)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
