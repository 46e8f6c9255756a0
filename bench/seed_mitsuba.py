#!/usr/bin/env python3
"""Lets a Mitsuba 0.6 build draw new random numbers for each seed, for measurements of its
error across seeds (bench/mitsuba_equal_time.py; docs/performance.md, "Mitsuba's seeds").

Mitsuba 0.6 as released ignores the sampler's `seed` (its independent sampler always starts
from the same default seed, and says 'Unqueried attribute "seed"'), and its MLT draws the
luminance pass and the chains' start paths from a second generator that is seeded the same
way every run. So runs "with different seeds" share their random numbers, and their spread
understates Mitsuba's error. This edits two constructors of a checkout built by
../shared/tools/build-mitsuba.sh and rebuilds it:

  src/samplers/independent.cpp  the independent sampler seeds its generator from the
                                sampler's `seed` when the scene gives one;
  src/libbidir/rsampler.cpp     the replayable sampler (MLT's luminance pass and start
                                paths) seeds its first generator from MTS_LUMINANCE_SEED
                                when that is set.

Nothing else changes: without a seed the build renders what the released one does, at the
same speed. Keep the unedited build for timing tables if in doubt.

  bench/seed_mitsuba.py DEST        (DEST: build-mitsuba.sh's DEST; edits it in place)
"""
import os
import subprocess
import sys


def edit(path, old, new, marker):
    with open(path) as f:
        text = f.read()
    if marker in text:
        return False  # already edited
    if text.count(old) != 1:
        sys.exit(f"seed_mitsuba: {path}: the line to edit was not found once; is this Mitsuba 0.6?")
    with open(path, "w") as f:
        f.write(text.replace(old, new))
    return True


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__.strip().splitlines()[-1].strip())
    dest = sys.argv[1]
    sampler = os.path.join(dest, "src", "samplers", "independent.cpp")
    replayable = os.path.join(dest, "src", "libbidir", "rsampler.cpp")
    for path in (sampler, replayable):
        if not os.path.isfile(path):
            sys.exit(f"seed_mitsuba: {path}: not found; DEST must be a Mitsuba 0.6 checkout "
                     "built by build-mitsuba.sh")
    changed = edit(sampler,
                   'm_sampleCount = props.getSize("sampleCount", 4);\n        m_random = new Random();',
                   'm_sampleCount = props.getSize("sampleCount", 4);\n        m_random = '
                   'props.hasProperty("seed") ? new Random((uint64_t) props.getLong("seed")) '
                   ': new Random();',
                   'props.hasProperty("seed")')
    changed |= edit(replayable,
                    "ReplayableSampler::ReplayableSampler() : Sampler(Properties()) {\n"
                    "    m_initial = new Random();",
                    "ReplayableSampler::ReplayableSampler() : Sampler(Properties()) {\n"
                    '    const char *seed = std::getenv("MTS_LUMINANCE_SEED");\n'
                    "    m_initial = seed ? new Random((uint64_t) std::strtoull(seed, NULL, 10))"
                    " : new Random();",
                    "MTS_LUMINANCE_SEED")
    with open(replayable) as f:
        text = f.read()
    if "#include <cstdlib>" not in text:
        with open(replayable, "w") as f:
            f.write("#include <cstdlib>\n" + text)
    try:
        subprocess.run(["scons", "-j", str(os.cpu_count() or 2)], cwd=dest, check=True,
                       stdout=subprocess.DEVNULL)
    except (OSError, subprocess.CalledProcessError) as e:
        sys.exit(f"seed_mitsuba: {dest}: the rebuild failed ({e})")
    print(f"seed_mitsuba: {dest} {'edited and ' if changed else ''}built: the sampler's seed and "
          "MTS_LUMINANCE_SEED are honoured")


if __name__ == "__main__":
    main()
