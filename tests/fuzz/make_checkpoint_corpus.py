#!/usr/bin/env python3
"""Writes the seed corpus of the checkpoint fuzz target (fuzz_checkpoint.cpp) from real
checkpoints, made by `emlt render` with the settings that target renders with. Run it again
whenever the checkpoint format changes (checkpoint_file.h's kVersion), since the target's
seeds must be states the current build writes:

    tests/fuzz/make_checkpoint_corpus.py [build/emlt]

Each seed starts with the target's mode byte: 0 and a whole checkpoint file, or 1..8 and
the integrator-state section alone (pt, bdpt, mlt, gamlt, emlt, pssmlt, pssmlt-bdpt, mmlt). EMLT_STOP_AFTER stops a
render as Ctrl-C would, so that the states cover a pass, the direct-light phase and a sweep
cut short as well as finished renders. Regression inputs (regression-*) are left alone."""
import os
import struct
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CORPUS = os.path.join(ROOT, "tests/fuzz/corpus/checkpoint")
MODES = {"pt": 1, "bdpt": 2, "mlt": 3, "gamlt": 4, "emlt": 5, "pssmlt": 6, "pssmlt-bdpt": 7,
         "mmlt": 8}
# The command line of a mode's integrator (checkpoint_resume.h: "pssmlt-bdpt" is pssmlt over BDPT).
INTEGRATOR_ARGS = {"pssmlt-bdpt": ["--integrator", "pssmlt", "--pss-tracer", "bdpt"]}
# Must match CheckpointFixture::settings (checkpoint_resume.h).
ARGS = ["--spp", "2", "--mpp", "2", "--bootstrap", "256", "--chains", "4", "--ensemble-size", "2",
        "--threads", "1", "--width", "4", "--height", "4", "-q"]
# name: integrator, EMLT_STOP_AFTER (None: the render finishes), also as a whole file.
# A 4 x 4 render at 2 per pixel makes 32 samples; MLT's direct-light pass comes first.
SEEDS = {
    "pt-mid-pass": ("pt", 5, True),
    "pt-finished": ("pt", None, False),
    "bdpt-mid-pass": ("bdpt", 5, True),
    "bdpt-finished": ("bdpt", None, False),
    "mlt-direct-phase": ("mlt", 20, False),
    "mlt-mid-sweep": ("mlt", 50, True),
    "mlt-finished": ("mlt", None, False),
    "gamlt-mid-sweep": ("gamlt", 50, False),
    "emlt-mid-sweep": ("emlt", 50, False),
    "emlt-finished": ("emlt", None, False),
    "pssmlt-mid-sweep": ("pssmlt", 45, True),
    "pssmlt-finished": ("pssmlt", None, False),
    "pssmlt-bdpt-mid-sweep": ("pssmlt-bdpt", 45, False),
    "mmlt-mid-sweep": ("mmlt", 45, False),
    "mmlt-finished": ("mmlt", None, False),
}


def state_section(data):
    # checkpoint_file.cpp: "EMLTCKPT", version, byte order, payload length, payload
    # ([header block][state block], each a u64 length and its bytes), checksum.
    header_size = struct.unpack_from("<Q", data, 24)[0]
    state_at = 24 + 8 + header_size
    state_size = struct.unpack_from("<Q", data, state_at)[0]
    return data[state_at + 8:state_at + 8 + state_size]


def main():
    emlt = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build/emlt"))
    scene = os.path.join(ROOT, "scenes/cornell-box/scene.json")
    os.makedirs(CORPUS, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        for name, (integrator, stop_after, whole_file) in SEEDS.items():
            checkpoint = os.path.join(tmp, name + ".ck")
            env = dict(os.environ)
            env.pop("EMLT_STOP_AFTER", None)
            if stop_after is not None:
                env["EMLT_STOP_AFTER"] = str(stop_after)
            run = subprocess.run([emlt, "render", scene,
                                  *INTEGRATOR_ARGS.get(integrator, ["--integrator", integrator]),
                                  *ARGS, "-o",
                                  os.path.join(tmp, name + ".exr"), "--checkpoint", checkpoint],
                                 env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
            if run.returncode != (0 if stop_after is None else 130):
                sys.exit(f"{name}: emlt exited {run.returncode}: {run.stderr.decode()}")
            with open(checkpoint, "rb") as f:
                data = f.read()
            with open(os.path.join(CORPUS, f"state-{name}"), "wb") as f:
                f.write(bytes([MODES[integrator]]) + state_section(data))
            if whole_file:
                with open(os.path.join(CORPUS, f"file-{name}"), "wb") as f:
                    f.write(bytes([0]) + data)


if __name__ == "__main__":
    main()
