#!/usr/bin/env python3
"""Times the CPU phases of `nephele render SCENE` for several binaries, interleaved (issue 19).

Usage: tools/render_phases.py SCENE ROUNDS BINARY [BINARY ...]

Each round runs every binary once, in turn, with NEPHELE_LOG=debug, and takes the time between
its log lines: "memory after start-up" -> "memory after scene preparation" (the basemaps read or
warped, and uploaded) and "memory after basemap images dropped" -> "memory after volume load"
(the .nph timestep read and decoded) and "memory after volume load" -> "memory after volume upload"
(the voxel checks, column depths, occupancy and textures; a one-shot render of a .nph decodes its
chunk there, a layer at a time). Prints one line per run, then the medians per binary.
The first run of a new build warps its basemaps again (the cache is keyed by the binary): run a
warm-up round first or read the medians.
"""
import os
import statistics
import subprocess
import sys
import time

PHASES = [("scene preparation", "memory after start-up", "memory after scene preparation"),
          ("volume load", "memory after basemap images dropped", "memory after volume load"),
          ("volume upload", "memory after volume load", "memory after volume upload")]


def run(binary, scene):
    env = dict(os.environ, NEPHELE_LOG="debug")
    p = subprocess.Popen([binary, "render", scene], stderr=subprocess.STDOUT, stdout=subprocess.PIPE, text=True,
                         env=env)
    t0 = time.time()
    marks = {}
    for line in p.stdout:
        t = time.time() - t0
        for _, a, b in PHASES:
            for key in (a, b):
                if key in line and key not in marks:
                    marks[key] = t
    if p.wait() != 0:
        sys.exit(f"{binary} render {scene} failed")
    return [marks[b] - marks[a] for _, a, b in PHASES]


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    scene, rounds, binaries = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
    times = {b: [] for b in binaries}
    for _ in range(rounds):
        for b in binaries:
            t = run(b, scene)
            times[b].append(t)
            print(f"{b}: " + ", ".join(f"{name} {v:.3f} s" for (name, _, _), v in zip(PHASES, t)), flush=True)
    for b in binaries:
        med = [statistics.median(t[i] for t in times[b]) for i in range(len(PHASES))]
        print(f"median {b}: " + ", ".join(f"{name} {v:.3f} s" for (name, _, _), v in zip(PHASES, med)))


if __name__ == "__main__":
    main()
