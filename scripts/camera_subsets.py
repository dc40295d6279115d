#!/usr/bin/env python3
"""Runs a job on every subset of its cameras and prints one markdown table row per subset.

    python3 scripts/camera_subsets.py configs/jobs/vsb_exp_a.yaml --cameras cam1,cam2,cam3 \
        --placement 431,555,-460 --tool-z 66 --robot ur3 --tool tool

Each subset is `cellmetry run JOB --without <camera> ...` into a folder of its own under
--out (default results/camera_subsets/<job name>). With --placement (and --tool-z), each row
says how far the base (and the tool's z) lies from that independent truth, in mm and in its
sigma: what docs/real-data.md's scoreboard quotes.
"""
import argparse
import itertools
import json
import math
import os
import subprocess
import sys


def run(cellmetry, job, without, out):
    command = [cellmetry, "--quiet", "run", job, "-o", out]
    for camera in without:
        command += ["--without", camera]
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "result.json"), encoding="utf-8") as f:
        return json.load(f)


def row(name, result, robot, tool, placement, tool_z):
    base = result["frames"][robot + ".base"]
    xyz, sigma = base["xyz_mm"], base["sigma_xyz_mm"]
    cells = [name, "(%.2f, %.2f, %.2f)" % tuple(xyz)]
    if placement:
        d = [xyz[i] - placement[i] for i in range(3)]
        worst = max(abs(d[i]) / sigma[i] if sigma[i] else math.inf for i in range(3))
        cells.append("(%.1f, %.1f, %.1f): **%.1f**" % (*d, math.sqrt(sum(v * v for v in d))))
        cells.append("(%.1f, %.1f, %.1f)" % tuple(sigma))
        cells.append("%.1f" % worst)
    else:
        cells.append("(%.1f, %.1f, %.1f)" % tuple(sigma))
    t = result["frames"][tool]
    z, sz = t["xyz_mm"][2], t["sigma_xyz_mm"][2]
    off = " (%.1fσ)" % (abs(z - tool_z) / sz) if tool_z else ""
    cells.append("%.2f ± %.2f%s" % (z, sz, off))
    held_out = result["held_out"]
    if held_out.get("folds", 0) > 0:
        cells.append("%.2f ± %.2f" % (held_out["total_mm"]["norm"], held_out["total_se_mm"]))
    else:
        cells.append("—")
    return "| " + " | ".join(cells) + " |"


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("job")
    parser.add_argument("--cameras", required=True, help="the recording's cameras, a,b,c")
    parser.add_argument("--robot", default="ur3")
    parser.add_argument("--tool", default="tool")
    parser.add_argument("--placement", help="the base's measured position x,y,z (mm)")
    parser.add_argument("--tool-z", type=float, help="the tool's known z (mm)")
    parser.add_argument("--out", help="where the results go")
    parser.add_argument("--cellmetry", default="build/bin/cellmetry")
    args = parser.parse_args()
    cameras = args.cameras.split(",")
    placement = [float(v) for v in args.placement.split(",")] if args.placement else None
    name = os.path.splitext(os.path.basename(args.job))[0]
    out = args.out or os.path.join("results", "camera_subsets", name)
    header = ["cameras", "base (mm)"]
    header += ["base − placement (mm)", "σ base (mm)", "worst error / σ"] if placement else \
              ["σ base (mm)"]
    header += ["tool z (mm)", "held-out RMS (mm)"]
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for size in range(len(cameras), 0, -1):
        for subset in itertools.combinations(cameras, size):
            without = [c for c in cameras if c not in subset]
            folder = os.path.join(out, "+".join(subset))
            result = run(args.cellmetry, args.job, without, folder)
            print(row(", ".join(subset), result, args.robot, args.tool, placement, args.tool_z))
            sys.stdout.flush()


if __name__ == "__main__":
    main()
