"""Surveys pbrt-v4 scene texts: which of them emlt reads exactly, which it approximates or
refuses in part, and which it cannot read at all.

    python3 -m tools.conformance.pbrt_survey TEXTS [--emlt build/emlt] [--manifest FILE]
        [--work DIR] [--markdown FILE] [--summary] [--only SCENE ...]

TEXTS is a folder laid out as the mmp/pbrt-v4-scenes repository, holding the scene texts
(.pbrt files) that were fetched; their meshes and images need not be there. The folder is
copied to a scratch folder (--work), where every file a scene names but the folder lacks
gets a stand-in:

  * a PLY mesh: one triangle with a position, a normal and a (u, v) per vertex, so that
    whatever the scene's `plymesh` does with normals or texture coordinates has them;
  * an image (.exr, .hdr, .pfm, .png): a 4x4 grey image of that format, written here with
    the standard library (pbrt's environment maps must be square; 4x4 is);
  * a .pbrt file (an `Include`/`Import` that was not fetched, most often for its size;
    gzip-compressed when its name ends in .gz): one emitting triangle (so that a scene
    whose geometry or lights all lie in such files still loads and the rest of it is
    checked), and the scene is then marked *partial*: its verdict covers only the texts
    that were read;
  * anything else (volume grids, measured BSDFs, spectra): an empty file, which emlt names
    in its error if it reads it.

So "exact" here means: every directive, shape type, material, texture, light, camera, film,
sampler and integrator setting in the texts read is read exactly (no approximated or
unsupported item in `emlt info`'s verdict); it says nothing about the meshes' or images'
contents, which were stand-ins.

The top-level scenes are the .pbrt files of TEXTS that have a `WorldBegin`. Each is run as
`emlt info --json SCENE`; a file it names but which is missing is found from the scene's
text before the run and, should emlt still name one ("... not found"), after it, up to a
few times. The table (markdown) lists per scene: exact / approximated (its items) /
unsupported (its items) / fails to load (emlt's one-line error), with the items' messages
stripped of file and line and counted.

--manifest names a tab-separated file `path<TAB>commit<TAB>chars` of the texts that were
fetched (the repository's path, the commit the text came from, its length in characters);
a text whose length differs is flagged in the table, so a copy that lost or gained
characters is seen. Standard library only: no network, no numpy.
"""
import argparse
import collections
import gzip
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

from tools import ROOT

IMAGE_EXTENSIONS = (".exr", ".hdr", ".pfm", ".png")


# ---- stand-ins ---------------------------------------------------------------------------


def ply_stand_in():
    # ASCII keeps it readable; emlt's PLY reader takes ascii and binary alike.
    return (
        "ply\nformat ascii 1.0\nelement vertex 3\n"
        "property float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        "property float u\nproperty float v\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n0 1 0 0 0 1 0 1\n3 0 1 2\n"
    ).encode()


def png_stand_in(size=4, value=128):
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    rows = b"".join(b"\x00" + bytes([value]) * (3 * size) for _ in range(size))
    header = struct.pack(">IIBBBBB", size, size, 8, 2, 0, 0, 0)  # 8-bit RGB
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) +
            chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def pfm_stand_in(size=4, value=0.5):
    return b"PF\n%d %d\n-1.0\n" % (size, size) + struct.pack("<f", value) * (3 * size * size)


def hdr_stand_in(size=4):
    # Radiance RGBE, flat (not run-length encoded) scanlines: 0.5 is mantissa 128, exponent 128.
    return (b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (size, size) +
            bytes([128, 128, 128, 128]) * (size * size))


def exr_stand_in(size=4, value=0.5):
    # A scanline OpenEXR file without compression, one line a block, float B, G, R channels
    # (channels are stored in name order).
    def attribute(name, kind, data):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(data)) + data

    channels = b"".join(c + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in (b"B", b"G", b"R"))
    box = struct.pack("<iiii", 0, 0, size - 1, size - 1)
    header = (struct.pack("<ii", 20000630, 2) +
              attribute("channels", "chlist", channels + b"\0") +
              attribute("compression", "compression", b"\0") +
              attribute("dataWindow", "box2i", box) +
              attribute("displayWindow", "box2i", box) +
              attribute("lineOrder", "lineOrder", b"\0") +
              attribute("pixelAspectRatio", "float", struct.pack("<f", 1.0)) +
              attribute("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0)) +
              attribute("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0")
    line = struct.pack("<f", value) * (3 * size)
    block = lambda y: struct.pack("<ii", y, len(line)) + line
    first = len(header) + 8 * size
    offsets = b"".join(struct.pack("<Q", first + y * len(block(y))) for y in range(size))
    return header + offsets + b"".join(block(y) for y in range(size))


def stand_in_for(path):
    if path.lower().endswith(".gz"):
        # pbrt reads gzip-compressed PLY meshes and scene files (`.ply.gz`, `.pbrt.gz`).
        return gzip.compress(stand_in_for(path[:-3]), mtime=0)
    ext = os.path.splitext(path)[1].lower()
    if ext == ".pbrt":
        # A scene text that was not fetched: one emitting triangle, so that a scene whose
        # geometry or lights all lie in such files still loads and the rest is checked.
        return (b"# stand-in for a text that was not fetched\n"
                b'AttributeBegin\n  AreaLightSource "diffuse"\n'
                b'  Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2]\n'
                b"AttributeEnd\n")
    if ext == ".spd":
        # A sampled spectrum file: wavelength (nm), value pairs.
        return b"300 1\n800 1\n"
    if ext == ".ply":
        return ply_stand_in()
    if ext == ".png":
        return png_stand_in()
    if ext == ".pfm":
        return pfm_stand_in()
    if ext == ".hdr":
        return hdr_stand_in()
    if ext == ".exr":
        return exr_stand_in()
    return b""


# ---- what a scene names ------------------------------------------------------------------

# A string parameter's value ("string filename" "x" or [ "x" ]) and an Include/Import.
STRING_PARAM = re.compile(r'"\s*string\s+(\w+)\s*"\s*\[?\s*"([^"]*)"')
INCLUDE = re.compile(r'^\s*(?:Include|Import)\s+"([^"]*)"', re.M)
FILE_PARAMS = {"filename", "mapname", "bumpmap"}


def strip_comments(text):
    return re.sub(r'#[^\n"]*$', "", text, flags=re.M)


def named_files(text):
    text = strip_comments(text)
    names = [m.group(2) for m in STRING_PARAM.finditer(text) if m.group(1) in FILE_PARAMS]
    names += [m.group(1) for m in INCLUDE.finditer(text)]
    return [n for n in names if n]


class Scene:
    def __init__(self, rel):
        self.rel = rel
        self.stand_ins = []  # what the scene names that was written here
        self.partial = []  # of those, the scene texts (.pbrt) that were not fetched


# Every stand-in written in this run (relative paths): scenes of one folder share them.
WRITTEN = set()


def add_stand_in(root, base_dir, name, scene):
    """Makes sure NAME (relative to the scene's directory) exists, writing a stand-in when
    the fetched texts lack it, and records it on the scene when it is one. Returns whether
    the scene gained a stand-in."""
    path = os.path.normpath(os.path.join(root, base_dir, name))
    if not path.startswith(root + os.sep):
        return False
    rel = os.path.relpath(path, root)
    if not os.path.exists(path):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(stand_in_for(path))
        WRITTEN.add(rel)
    if rel not in WRITTEN or rel in scene.stand_ins:
        return False
    scene.stand_ins.append(rel)
    if rel.endswith((".pbrt", ".pbrt.gz")):
        scene.partial.append(rel)
    return True


def prepare(root, scene):
    """Writes stand-ins for what the scene and the texts it includes name, following
    includes that were fetched."""
    base_dir = os.path.dirname(scene.rel)
    todo, seen = [scene.rel], set()
    while todo:
        rel = todo.pop()
        if rel in seen:
            continue
        seen.add(rel)
        with open(os.path.join(root, rel), encoding="utf-8", errors="replace") as f:
            text = f.read()
        for name in named_files(text):
            add_stand_in(root, base_dir, name, scene)
            target = os.path.relpath(os.path.normpath(os.path.join(root, base_dir, name)), root)
            if target.endswith(".pbrt") and target not in WRITTEN:
                todo.append(target)


NOT_FOUND = re.compile(r"'([^']+)' not found|(\S+): [^:]*file not found")


def run_info(emlt, root, scene, tries=8):
    for _ in range(tries):
        proc = subprocess.run([emlt, "info", "--json", scene.rel], cwd=root,
                              capture_output=True, text=True, errors="replace")
        if proc.returncode == 0:
            return json.loads(proc.stdout), None
        error = (proc.stderr.strip().splitlines() or ["(no message)"])[-1]
        missing = NOT_FOUND.search(error)
        name = missing and (missing.group(1) or missing.group(2))
        if not name or not add_stand_in(root, os.path.dirname(scene.rel), name, scene):
            return None, error
    return None, error


# ---- the table ---------------------------------------------------------------------------

LOCATION = re.compile(r"^\S+?: line \d+: ")

# Short names for the summary: the first pattern an item's message matches names it
# (an item that matches none keeps its message up to the first ';').
LABELS = [
    (r'PixelFilter "gaussian"', "Gaussian pixel filter (pbrt's default)"),
    (r"equal-area octahedral map", "image infinite light (resampled to lat-long)"),
    (r"only one infinite light", "a second infinite light"),
    (r'"coateddiffuse": approximated', "coateddiffuse"),
    (r'"coatedconductor": approximated', "coatedconductor"),
    (r"as Mitsuba's RGB values for that metal", "named metal spectrum (RGB)"),
    (r"spectrum \"[^\"]*\.spd\"", "spectrum file (.spd)"),
    (r"'blackbody ", "blackbody (RGB)"),
    (r"a sampled spectrum as RGB", "sampled spectrum (RGB)"),
    (r"glass-\w+", "named glass (index at 587.6 nm)"),
    (r'material "measured"', "measured material"),
    (r'material "subsurface"', "subsurface material"),
    (r'material "hair"', "hair material"),
    (r"'texture displacement'", "displacement (bump) texture"),
    (r"MakeNamedMedium|MediumInterface", "participating media"),
    (r"Film iso", "Film iso (exposure scale)"),
    (r"maxcomponentvalue", "Film maxcomponentvalue"),
    (r"whitebalance", "Film whitebalance"),
    (r"Film sensor", "Film sensor"),
    (r"'regularize'", "Integrator regularize"),
    (r'Integrator "sppm"', "Integrator sppm (as bdpt)"),
    (r"tessellated", "disk or cylinder (tessellated)"),
    (r"zmin|zmax|phimax|innerradius", "partial quadric"),
    (r"ActiveTransform", "animated transform"),
    (r"conedeltaangle is linear", "spot falloff (linear in angle)"),
    (r"textured roughness", "textured roughness (remapped)"),
    (r"texture type '\w+' is not supported", "procedural texture (wrinkled, windy, ...)"),
    (r'mapping "\w+" is not supported', "texture mapping other than uv"),
    (r"a mix of varying textures", "mix of varying textures"),
    (r"'float scale' of Film", "Film scale"),
]


def label(message):
    for pattern, name in LABELS:
        if re.search(pattern, message):
            return name
    return message.split(";")[0]


def item_counts(warnings, kind):
    counts = collections.Counter(LOCATION.sub("", w["message"]) for w in warnings
                                 if w["kind"] == kind)
    return [f"{m} (×{n})" if n > 1 else m for m, n in sorted(counts.items())]


def label_counts(warnings, kind):
    counts = collections.Counter(label(LOCATION.sub("", w["message"])) for w in warnings
                                 if w["kind"] == kind)
    return [f"{m} ×{n}" if n > 1 else m for m, n in sorted(counts.items())]


def is_scene(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        return re.search(r"^\s*WorldBegin\b", strip_comments(f.read()), re.M) is not None


def read_manifest(path):
    manifest = {}
    if path:
        with open(path, encoding="utf-8") as f:
            for line in f:
                if line.strip() and not line.startswith("#"):
                    rel, commit, chars = line.rstrip("\n").split("\t")[:3]
                    manifest[rel] = (commit, int(chars))
    return manifest


def length_mismatches(texts, manifest):
    bad = []
    for rel, (_, chars) in manifest.items():
        path = os.path.join(texts, rel)
        if os.path.exists(path):
            with open(path, encoding="utf-8", errors="replace", newline="") as f:
                if len(f.read()) != chars:
                    bad.append(rel)
    return bad


def md(text):
    return text.replace("|", "\\|").replace("\n", " ")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("texts", help="folder of fetched pbrt-v4 scene texts (repository layout)")
    parser.add_argument("--emlt", default=os.path.join(ROOT, "build", "emlt"))
    parser.add_argument("--manifest", help="path<TAB>commit<TAB>chars of the fetched texts")
    parser.add_argument("--work", help="scratch folder for the copy with stand-ins "
                        "(default: a temporary one, removed afterwards)")
    parser.add_argument("--markdown", help="also write the table to this file")
    parser.add_argument("--summary", action="store_true",
                        help="short names for the items, and how many scenes each reason "
                        "keeps from exact")
    parser.add_argument("--only", action="append", default=[],
                        help="survey only this scene (path under TEXTS; repeatable)")
    args = parser.parse_args(argv)

    texts = os.path.abspath(args.texts)
    emlt = os.path.abspath(args.emlt)
    manifest = read_manifest(args.manifest)
    work = args.work or tempfile.mkdtemp(prefix="pbrt-survey-")
    root = os.path.join(os.path.abspath(work), "scenes")
    if os.path.exists(root):
        shutil.rmtree(root)
    shutil.copytree(texts, root)

    scenes = []
    for dirpath, _, files in os.walk(texts):
        for name in files:
            rel = os.path.relpath(os.path.join(dirpath, name), texts)
            if name.endswith(".pbrt") and is_scene(os.path.join(dirpath, name)):
                if not args.only or rel in args.only:
                    scenes.append(rel)
    scenes.sort()

    rows, tally, reasons = [], collections.Counter(), collections.Counter()
    for rel in scenes:
        scene = Scene(rel)
        prepare(root, scene)
        result, error = run_info(emlt, root, scene)
        if error is not None:
            verdict, detail = "fails to load", error.replace(root + os.sep, "")
            short = detail.replace("emlt: error: ", "")
            # emlt reads a gzip-compressed file as it is: name the cause, not its bytes.
            gz = re.match(r"(\S+\.(pbrt|ply)\.gz): ", short)
            if gz:
                short = gz.group(1) + ": gzip-compressed " + (
                    "scene text" if gz.group(2) == "pbrt" else "PLY mesh") + " not read"
            detail = short = "".join(c if c.isprintable() else "?" for c in short)
            reasons["fails to load: " + re.sub(r"^\S+: (line \d+: )?", "", short)] += 1
        else:
            warnings = result["warnings"]
            approx = item_counts(warnings, "approximated")
            unsupported = item_counts(warnings, "unsupported")
            verdict = "exact" if not approx and not unsupported else (
                "unsupported" if unsupported else "approximated")
            parts = []
            if unsupported:
                parts.append("unsupported: " + "; ".join(unsupported))
            if approx:
                parts.append("approximated: " + "; ".join(approx))
            detail = " — ".join(parts)
            short_parts = []
            for kind, word in (("unsupported", "unsupported"), ("approximated", "approximated")):
                labels = label_counts(warnings, kind)
                if labels:
                    short_parts.append(word + ": " + ", ".join(labels))
                for name in {label(LOCATION.sub("", w["message"])) for w in warnings
                             if w["kind"] == kind}:
                    reasons[f"{word}: {name}"] += 1
            short = "; ".join(short_parts)
        if scene.partial:
            verdict += " (partial)"
            detail = ("not read (stand-in): " + ", ".join(scene.partial) +
                      (". " + detail if detail else ""))
            short = (f"{len(scene.partial)} included text(s) not read. " + short).strip()
        tally[verdict] += 1
        rows.append((rel, verdict, detail, short))
        print(f"{rel}: {verdict}", file=sys.stderr)

    if args.summary:
        lines = ["| scene | verdict | what keeps it from exact (×N: N items) |", "|---|---|---|"]
        lines += [f"| `{rel}` | {verdict} | {md(short)} |" for rel, verdict, _, short in rows]
        lines += ["", "| reason | scenes |", "|---|---|"]
        lines += [f"| {md(name)} | {n} |" for name, n in
                  sorted(reasons.items(), key=lambda kv: (-kv[1], kv[0]))]
    else:
        lines = ["| scene | verdict | items (file and line stripped; ×N: N times) |",
                 "|---|---|---|"]
        lines += [f"| `{rel}` | {verdict} | {md(detail)} |" for rel, verdict, detail, _ in rows]
    lines.append("")
    lines.append("Tally: " + ", ".join(f"{v} {n}" for v, n in sorted(tally.items())) +
                 f" (of {len(rows)} scenes).")
    bad = length_mismatches(texts, manifest)
    if bad:
        lines.append("Texts whose length differs from the manifest's: " + ", ".join(bad) + ".")
    table = "\n".join(lines) + "\n"
    sys.stdout.write(table)
    if args.markdown:
        with open(args.markdown, "w", encoding="utf-8") as f:
            f.write(table)
    if not args.work:
        shutil.rmtree(work)
    return 0


if __name__ == "__main__":
    sys.exit(main())
