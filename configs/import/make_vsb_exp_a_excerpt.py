#!/usr/bin/env python3
"""Writes vsb_exp_a_excerpt.csv: an excerpt of the VSB experiment A recording
(tests/data/vsb/exp_a) in the form of the published MATLAB table it was converted from --
positions in metres, rotations as Euler XYZ angles -- so that docs/your-data.md can show
`cellmetry import` on a table as a user holds it.

Every 8th commanded pose (32 poses), the first 3 of its 10 captures, all three cameras: 288
rows, one per capture and camera. Angles are intrinsic XYZ in degrees (R = Rx(a) Ry(b) Rz(c)),
positions in m; the joint readings stay in rad as the UR controller gives them. No value is
changed beyond those conversions (the rotation vector's rotation matrix, then its angles).

Run from the repository root: python3 configs/import/make_vsb_exp_a_excerpt.py
"""
import csv
import math
import os

SOURCE = "tests/data/vsb/exp_a"
TARGET = "configs/import/vsb_exp_a_excerpt.csv"
POSE_STEP, CAPTURES = 8, 3


def rotation(rvec):
    angle = math.sqrt(sum(v * v for v in rvec))
    if angle == 0:
        return [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    x, y, z = (v / angle for v in rvec)
    c, s, t = math.cos(angle), math.sin(angle), 1 - math.cos(angle)
    return [[t * x * x + c, t * x * y - s * z, t * x * z + s * y],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c]]


def euler_xyz_intrinsic_deg(R):
    b = math.asin(max(-1.0, min(1.0, R[0][2])))
    a = math.atan2(-R[1][2], R[2][2])
    c = math.atan2(-R[0][1], R[0][0])
    return [math.degrees(v) for v in (a, b, c)]


samples = {row["sample"]: row for row in csv.DictReader(open(os.path.join(SOURCE, "samples.csv")))}
seen = {}  # (sample, camera) -> {target: observation}
for o in csv.DictReader(open(os.path.join(SOURCE, "observations.csv"))):
    seen.setdefault((o["sample"], o["camera"]), {})[o["target"]] = o

captures_of_pose = {}
rows = []
for (sample, camera), targets in seen.items():
    s = samples[sample]
    pose = int(s["pose"])
    if pose % POSE_STEP:
        continue
    kept = captures_of_pose.setdefault(pose, [])
    if sample not in kept:
        if len(kept) == CAPTURES:
            continue
        kept.append(sample)
    row = [sample, s["pose"], camera] + [s["q%d" % j] for j in range(1, 7)]
    for target in ("tool", "world"):
        o = targets[target]
        row += ["%.9f" % (float(o[axis]) / 1000.0) for axis in "xyz"]
        angles = euler_xyz_intrinsic_deg(rotation([float(o[k]) for k in ("rx", "ry", "rz")]))
        row += ["%.7f" % a for a in angles]
    rows.append(row)

with open(TARGET, "w", newline="") as out:
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["capture", "pose", "camera", "q1", "q2", "q3", "q4", "q5", "q6",
                     "tool_x", "tool_y", "tool_z", "tool_eul_x", "tool_eul_y", "tool_eul_z",
                     "world_x", "world_y", "world_z", "world_eul_x", "world_eul_y", "world_eul_z"])
    writer.writerows(rows)
print("%d rows -> %s" % (len(rows), TARGET))
