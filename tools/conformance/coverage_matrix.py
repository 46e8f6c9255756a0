"""Writes docs/compatibility-matrix.md: every plugin and parameter of Mitsuba 0.6, each marked
as emlt's loader itself reads it.

    python3 -m tools.conformance.coverage_matrix --emlt build/emlt          (regenerate)
    python3 -m tools.conformance.coverage_matrix --emlt build/emlt --check  (CTest: differs?)

The list of plugins and parameters is tools/conformance/mitsuba06_plugins.json (extracted
from Mitsuba's source by extract_mitsuba_plugins.py). Nothing here says what emlt supports:
for each plugin a probe scene (coverage_probes.py) is loaded by `emlt info --json`, then
one for each value tried of each parameter, and the loader's own warnings classify it:

- no new warning, or only a note that changes no image: *exact*; so is a file refused
  where Mitsuba refuses it too (the error says "Mitsuba refuses");
- a note that the parameter steers only sampling: *sampling-only* (a note, not an item);
- an Approximated item: *approximated*, the warning saying how;
- an Unsupported item, a skipped element or a refused file: *unsupported*, the warning or
  the error saying why.

A parameter's warnings are those its probe has beyond the plugin's bare probe; of several
values tried (a boolean both ways, a colour and a texture) the worst counts. The parameters
of an unsupported plugin are unsupported with it. So the matrix changes when the loader
does, and the CTest test `compatibility_matrix` fails until it is regenerated.
"""
import argparse
import collections
import concurrent.futures
import difflib
import glob
import json
import os
import re
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

from tools import ROOT
from tools.conformance import coverage_probes

DATA = os.path.join(ROOT, "tools", "conformance", "mitsuba06_plugins.json")
OUTPUT = os.path.join(ROOT, "docs", "compatibility-matrix.md")
SCENES = os.path.join(ROOT, "tests", "conformance", "scenes")
COMMAND = "python3 -m tools.conformance.coverage_matrix --emlt build/emlt"

STATUSES = ["exact", "sampling-only", "approximated", "unsupported"]
RANK = {status: i for i, status in enumerate(STATUSES)}
TITLES = {
    "bsdf": "BSDFs", "emitter": "Emitters", "sensor": "Sensors", "film": "Films",
    "rfilter": "Reconstruction filters", "texture": "Textures", "shape": "Shapes",
    "integrator": "Integrators", "sampler": "Samplers", "medium": "Participating media",
    "phase": "Phase functions", "subsurface": "Subsurface scattering",
    "volume": "Volume data sources",
}
# The loader's notes for parameters that change the noise only (note_sampling_only, and the
# integrators' convergence parameters).
SCENES_SHOWN = 6  # conformance scenes named per plugin
SAMPLING_NOTE = re.compile(r"steers? only|change the noise, not the image")
# The loader's words when it refuses what Mitsuba 0.6 refuses too: read as Mitsuba reads it.
REFUSED_BY_MITSUBA = re.compile(r"Mitsuba refuses")


def normalise(message, folder):
    """A warning without what changes from run to run or probe to probe: the probe's path
    and the line numbers (a parameter probe has one line more than the bare one)."""
    text = message.replace(folder + os.sep, "")
    text = re.sub(r"^[\w.-]+\.xml: ", "", text)
    text = re.sub(r"\bline \d+: ", "", text)
    text = re.sub(r" \(line \d+\)", "", text)
    text = re.sub(r" at line \d+", "", text)
    return text


def load(emlt, path, folder):
    """(warnings [(kind, message)], error or None) of `emlt info --json path`."""
    run = subprocess.run([emlt, "info", "--json", path], capture_output=True, text=True)
    if run.returncode != 0:
        lines = (run.stderr or run.stdout).strip().splitlines() or ["exit %d" % run.returncode]
        error = re.sub(r"^(emlt: )?error: ", "", lines[-1])
        return [], normalise(error, folder)
    report = json.loads(run.stdout)
    return [(w["kind"], normalise(w["message"], folder)) for w in report["warnings"]], None


def classify(warnings, error):
    """(status, [the loader's words]) from the warnings a probe adds."""
    if error is not None:
        if REFUSED_BY_MITSUBA.search(error):
            return "exact", ["refused, as by Mitsuba: " + error]
        return "unsupported", ["refused: " + error]
    status, words = "exact", []
    for kind, message in warnings:
        if kind == "unsupported":
            found = "unsupported"
        elif kind == "approximated":
            found = "approximated"
        elif SAMPLING_NOTE.search(message):
            found = "sampling-only"
        else:
            found, message = "exact", "note: " + message
        status = max(status, found, key=RANK.get)
        words.append(message)
    return status, words


def added(warnings, bare):
    """The warnings of `warnings` beyond those of the bare probe (as multisets)."""
    rest = collections.Counter(bare)
    out = []
    for warning in warnings:
        if rest[warning]:
            rest[warning] -= 1
        else:
            out.append(warning)
    return out


def conformance_scenes():
    """(element, type) -> names of the conformance scenes whose XML uses it. A scene that
    emlt renders from its pbrt-v4 file (NAME.pbrt beside it) proves nothing about how emlt
    reads the XML, which only Mitsuba renders: it is left out."""
    uses = collections.defaultdict(set)
    for path in sorted(glob.glob(os.path.join(SCENES, "*.xml"))):
        name = os.path.splitext(os.path.basename(path))[0]
        if os.path.exists(os.path.join(SCENES, name + ".pbrt")):
            continue
        for node in ET.parse(path).iter():
            if node.get("type"):
                uses[(node.tag, node.get("type"))].add(name)
    return uses


def probe_all(data, emlt, workers):
    """Runs every probe; {(category, plugin, parameter or None, variant): (warnings, error)}."""
    jobs = []
    for category, plugins in data["categories"].items():
        for entry in plugins:
            plugin = entry["plugin"]
            jobs.append(((category, plugin, None, None),
                         coverage_probes.scene(category, plugin, [])))
            for param in entry["parameters"]:
                for element, value in coverage_probes.value_variants(category, plugin, param):
                    jobs.append(((category, plugin, param["name"], (element, value)),
                                 coverage_probes.scene(category, plugin,
                                                       [(element, param["name"], value)])))
    results = {}
    with tempfile.TemporaryDirectory(prefix="emlt-coverage-") as folder:
        folder = os.path.realpath(folder)
        os.symlink(os.path.join(ROOT, coverage_probes.ASSETS), os.path.join(folder, "assets"))
        paths = []
        for i, (_, text) in enumerate(jobs):
            path = os.path.join(folder, "probe%04d.xml" % i)
            with open(path, "w") as f:
                f.write(text)
            paths.append(path)
        with concurrent.futures.ThreadPoolExecutor(workers) as pool:
            outcomes = pool.map(lambda p: load(emlt, p, folder), paths)
            for (key, _), outcome in zip(jobs, outcomes):
                results[key] = outcome
    return results


def shown(variant):
    element, value = variant
    return "<%s>" % element if value is None else "%s %s" % (element, value)


def matrix(data, results):
    """{category: [(plugin entry, status, words, [(param, status, words)])]}."""
    out = {}
    for category, plugins in data["categories"].items():
        rows = []
        for entry in plugins:
            plugin = entry["plugin"]
            bare_warnings, bare_error = results[(category, plugin, None, None)]
            status, words = classify(bare_warnings, bare_error)
            params = []
            for param in entry["parameters"]:
                name = param["name"]
                variants = coverage_probes.value_variants(category, plugin, param)
                if status == "unsupported":
                    params.append((param, "unsupported", ["with its plugin"]))
                    continue
                if not variants:
                    # Given in every probe of the plugin (a mesh's filename): what the bare
                    # probe says about it.
                    mine = [w for w in bare_warnings if "'%s'" % name in w[1]]
                    params.append((param,) + classify(mine, None))
                    continue
                found = []
                for variant in variants:
                    warnings, error = results[(category, plugin, name, variant)]
                    found.append((variant,) + classify(added(warnings, bare_warnings), error))
                worst = max((s for _, s, _ in found), key=RANK.get)
                # Each message once, naming the values that gave it unless all did.
                by_message = collections.OrderedDict()
                for variant, s, w in found:
                    if s == worst or worst == "exact":  # an exact one's notes, of any value
                        for text in w:
                            by_message.setdefault(text, []).append(variant)
                said = [text if len(where) == len(variants) else
                        "(%s) %s" % (", ".join(shown(v) for v in where), text)
                        for text, where in by_message.items()]
                params.append((param, worst, said))
            rows.append((entry, status, words, params))
        out[category] = rows
    return out


def shown_default(param):
    """The manual's default in a few words ("0.5", "bk7 / 1.5046"), else the code's when it
    is a literal; "" when neither says it briefly."""
    doc = re.split(r",? i\.e\.|\(", param.get("default", ""))[0].strip()
    if doc and len(doc) <= 30:
        return doc
    code = param.get("code_default", "").strip()
    literal = re.fullmatch(r'(-?[\d.]+(?:e-?\d+)?)f?|(true|false)|"([^"]*)"', code)
    if literal and code != '""':
        return next(g for g in literal.groups() if g is not None)
    return ""


def cell(text):
    """Text safe in a Markdown table cell (the warnings quote XML elements)."""
    return (text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
            .replace("|", "\\|"))


def render(data, table, uses):
    counts = {}
    lines = [
        "# Mitsuba 0.6 coverage matrix",
        "",
        "<!-- Generated; do not edit. Regenerate with: %s -->" % COMMAND,
        "",
        "Generated by `%s` (the CTest test `compatibility_matrix` fails when this file "
        "differs from what the loader says). Every plugin and parameter of Mitsuba 0.6 "
        "as its source at commit [`%s`](%s/tree/%s) lists them "
        "([tools/conformance/mitsuba06_plugins.json](../tools/conformance/mitsuba06_plugins.json), "
        "extracted by "
        "[extract_mitsuba_plugins.py](../tools/conformance/extract_mitsuba_plugins.py)), "
        "each marked by what emlt's loader says about a probe scene that uses it "
        "([coverage_matrix.py](../tools/conformance/coverage_matrix.py)):"
        % (COMMAND, data["commit"][:12], data["mitsuba"], data["commit"]),
        "",
        "- **exact**: read as Mitsuba reads it, with no warning (or a note that changes no "
        "image, or refused where Mitsuba refuses it too); for a plugin, the [conformance scenes](conformance.md) whose XML uses it, or "
        "*exact by the loader, no conformance scene yet*;",
        "- **sampling-only**: it steers only how Mitsuba draws its samples, not the converged "
        "image; a note, never an item of the verdict;",
        "- **approximated**: emlt renders something close; the loader's warning says how;",
        "- **unsupported**: left out; the loader's warning (or its error) says why.",
        "",
        "A parameter is probed with its default (booleans both ways; a colour or number that "
        "may be a texture also as a checkerboard); the worst status of its values counts. "
        "`emlt info SCENE` gives the same words for a scene of your own, with its lines. "
        "See [compatibility.md](compatibility.md) for what each convention means.",
        "",
    ]
    summary = ["## Summary", "",
               "| Category | Plugins | exact | sampling-only | approximated | unsupported "
               "| Parameters | exact | sampling-only | approximated | unsupported |",
               "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|"]
    body = []
    totals = [collections.Counter(), collections.Counter()]
    for category, rows in table.items():
        plugin_counts, param_counts = collections.Counter(), collections.Counter()
        body += ["## %s (`<%s>`)" % (TITLES[category], category), "",
                 "| Plugin | Parameter | Status | Conformance scenes, or the loader's words |",
                 "|---|---|---|---|"]
        for entry, status, words, params in rows:
            plugin = entry["plugin"]
            plugin_counts[status] += 1
            notes = []
            scenes = sorted(uses.get((category, plugin), ()))
            if status == "exact" and not scenes:
                notes.append("**exact by the loader, no conformance scene yet**")
            elif scenes:
                # Those named after the plugin first; the base of every scene (a path
                # tracer, a box filter ...) would otherwise list the whole suite.
                scenes.sort(key=lambda name: (plugin not in name, name))
                listed = ", ".join(scenes[:SCENES_SHOWN])
                if len(scenes) > SCENES_SHOWN:
                    listed += " … (%d in all)" % len(scenes)
                notes.append("scenes: " + listed)
            notes += [cell(w) for w in words]
            title = " — " + cell(entry["description"]) if entry["description"] else ""
            body.append("| **%s**%s | | **%s** | %s |"
                        % (plugin, title, status, "<br>".join(notes)))
            for param, pstatus, pwords in params:
                param_counts[pstatus] += 1
                kind = "/".join(t for t in param.get("types", []) if t) or "?"
                default = shown_default(param)
                described = "`%s` (%s%s)" % (param["name"], kind,
                                             ", default " + cell(default) if default else "")
                if not param.get("documented"):
                    described += " †"
                body.append("| | %s | %s | %s |"
                            % (described, pstatus, "<br>".join(cell(w) for w in pwords)))
        body.append("")
        totals[0].update(plugin_counts)
        totals[1].update(param_counts)
        summary.append("| %s | %d | %s | %d | %s |" % (
            TITLES[category], sum(plugin_counts.values()),
            " | ".join(str(plugin_counts[s]) for s in STATUSES), sum(param_counts.values()),
            " | ".join(str(param_counts[s]) for s in STATUSES)))
        counts[category] = (plugin_counts, param_counts)
    summary.append("| **All** | **%d** | %s | **%d** | %s |" % (
        sum(totals[0].values()), " | ".join("**%d**" % totals[0][s] for s in STATUSES),
        sum(totals[1].values()), " | ".join("**%d**" % totals[1][s] for s in STATUSES)))
    summary += ["", "† not in the plugin's documentation: read by its code or its base class "
                "(an emitter's `samplingWeight`, a BSDF's `ensureEnergyConservation` ...).", ""]
    return "\n".join(lines + summary + body)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--emlt", default=os.path.join(ROOT, "build", "emlt"))
    parser.add_argument("--output", default=OUTPUT)
    parser.add_argument("--check", action="store_true",
                        help="write nothing; fail, printing the diff, if the file differs")
    parser.add_argument("--jobs", type=int, default=2, help="emlt info runs at once")
    args = parser.parse_args()
    with open(DATA) as f:
        data = json.load(f)
    results = probe_all(data, os.path.abspath(args.emlt), args.jobs)
    text = render(data, matrix(data, results), conformance_scenes())
    if args.check:
        with open(args.output) as f:
            committed = f.read()
        if committed == text:
            return 0
        sys.stdout.writelines(difflib.unified_diff(
            committed.splitlines(True), text.splitlines(True), args.output, "regenerated"))
        print("\n%s is out of date: the loader changed. Regenerate it with\n    %s"
              % (os.path.relpath(args.output, ROOT), COMMAND))
        return 1
    with open(args.output, "w") as f:
        f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
