#!/usr/bin/env python3
"""Compares two folders written by `scripts/regression.sh record` (see there).

Every file the steps wrote is compared after measurements of the run itself are masked: JSON keys
and CSV or markdown columns whose name says time or resident memory, and numbers followed by s /
ms / per second in text. Exits 1 and
lists the files that differ (with the first differing line) if any does, 0 otherwise.

JSON files are compared key by key: a key only the newer run has (a field added to a result) is
listed as added, not as a difference.

With --tolerance REL, numbers that differ by at most REL relative (or 1e-12 absolute) count as
equal: for a change that swaps one numerical method for an equivalent one (the last bits move).
"""
import json
import os
import re
import sys

TIMING_TEXT = re.compile(r"[-+]?\d+(\.\d+)?(e[-+]?\d+)?\s*(ms|s|µs|us|/s|frames/s|per second)\b")
TIMING_KEY = re.compile(r"time|seconds|elapsed|duration|per_second|rate_hz|resident_mb",
                        re.IGNORECASE)


def mask_json(value):
    if isinstance(value, dict):
        return {k: ("<time>" if TIMING_KEY.search(k) else mask_json(v)) for k, v in value.items()}
    if isinstance(value, list):
        return [mask_json(v) for v in value]
    return value


def mask_table_line(line, timing_columns):
    cells = line.split("|")
    return "|".join("<time>" if i in timing_columns else c for i, c in enumerate(cells))


def normalized_lines(path):
    name = os.path.basename(path)
    with open(path, "rb") as f:
        data = f.read()
    if name.endswith((".png", ".pgm", ".jpg")):
        return [data.hex()[:64] + " (%d bytes, hash %d)" % (len(data), hash(data))]
    text = data.decode("utf-8", errors="replace")
    if name.endswith(".json"):
        try:
            return json.dumps(mask_json(json.loads(text)), indent=1, sort_keys=True).splitlines()
        except ValueError:
            pass
    if name.endswith(".jsonl"):
        out = []
        for line in text.splitlines():
            try:
                out.append(json.dumps(mask_json(json.loads(line)), sort_keys=True))
            except ValueError:
                out.append(line)
        return sorted(out)  # appended as parallel workers finish: the order is not the content
    lines = text.splitlines()
    if name.endswith(".csv") and lines:
        header = lines[0].split(",")
        timing = {i for i, h in enumerate(header) if TIMING_KEY.search(h)}
        return [",".join("<time>" if i in timing else c for i, c in enumerate(l.split(",")))
                for l in lines]
    out, timing_columns = [], set()
    for line in lines:
        if line.lstrip().startswith("|"):
            cells = line.split("|")
            if any(TIMING_KEY.search(c) or re.search(r"\bms\b", c) for c in cells):
                timing_columns = {i for i, c in enumerate(cells)
                                  if TIMING_KEY.search(c) or re.search(r"\bms\b", c)}
            line = mask_table_line(line, timing_columns)
        else:
            timing_columns = set()
        if re.match(r"\s*(\w+_)?time", line):
            line = re.sub(r":.*", ": <time>", line)
        out.append(TIMING_TEXT.sub("<time>", line))
    return out


NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


def same_line(x, y, tolerance):
    if x == y:
        return True
    if tolerance <= 0 or NUMBER.sub("#", x) != NUMBER.sub("#", y):
        return False
    for a, b in zip(NUMBER.finditer(x), NUMBER.finditer(y)):
        u, v = float(a.group()), float(b.group())
        if abs(u - v) > max(1e-12, tolerance * max(abs(u), abs(v))):
            return False
    return True


def flatten(value, path=""):
    if isinstance(value, dict):
        out = {}
        for k, v in value.items():
            out.update(flatten(v, path + "/" + k))
        return out
    if isinstance(value, list) and any(isinstance(v, (dict, list)) for v in value):
        out = {}
        for i, v in enumerate(value):
            out.update(flatten(v, path + "[%d]" % i))
        return out
    return {path: json.dumps(value)}


def compare_json(path_a, path_b, tolerance):
    """(differences, added keys) of two JSON files, or None if either is not JSON."""
    try:
        a = flatten(mask_json(json.load(open(path_a))))
        b = flatten(mask_json(json.load(open(path_b))))
    except ValueError:
        return None
    diffs = ["%s: %s -> %s" % (k, a[k][:80], b.get(k, "(absent)")[:80])
             for k in sorted(a) if k not in b or not same_line(a[k], b[k], tolerance)]
    added = sorted(k for k in b if k not in a)
    return diffs, added


def files_under(root):
    found = set()
    for folder, _, names in os.walk(root):
        for n in names:
            found.add(os.path.relpath(os.path.join(folder, n), root))
    return found


def main(before, after, tolerance=0.0):
    skipped = set()
    for side in (before, after):
        logs = os.path.join(side, "logs")
        for n in os.listdir(logs):
            if n.endswith(".rc"):
                with open(os.path.join(logs, n)) as f:
                    if f.read().split()[0] == "124":
                        skipped.add(n[:-3])
    a_files = {f for f in files_under(before) if not f.endswith(".err")}
    b_files = {f for f in files_under(after) if not f.endswith(".err")}
    differ, added = [], []
    for f in sorted(a_files | b_files):
        if f.startswith("logs/") and f.endswith(".rc"):
            a = open(os.path.join(before, f)).read().split()[0] if f in a_files else None
            b = open(os.path.join(after, f)).read().split()[0] if f in b_files else None
            if a != b and f[5:-3] not in skipped:
                differ.append((f, "exit %s -> %s" % (a, b)))
            continue
        if f.startswith("tree/configs/") or f.startswith("tree/tests/"):
            continue
        if f not in a_files or f not in b_files:
            differ.append((f, "only in " + ("after" if f in b_files else "before")))
            continue
        if f.endswith(".json"):
            result = compare_json(os.path.join(before, f), os.path.join(after, f), tolerance)
            if result is not None:
                diffs, new_keys = result
                if diffs:
                    differ.append((f, "%d values differ, first %s" % (len(diffs), diffs[0])))
                if new_keys:
                    added.append((f, "%d keys added (%s ...)" % (len(new_keys), new_keys[0])))
                continue
        la = normalized_lines(os.path.join(before, f))
        lb = normalized_lines(os.path.join(after, f))
        if len(la) != len(lb) or not all(same_line(x, y, tolerance) for x, y in zip(la, lb)):
            for i, (x, y) in enumerate(zip(la + [""] * len(lb), lb + [""] * len(la))):
                if not same_line(x, y, tolerance):
                    differ.append((f, "line %d: %r -> %r" % (i + 1, x[:160], y[:160])))
                    break
    for name in sorted(skipped):
        print("not compared (over the time limit): %s" % name)
    for f, why in added:
        print("ADDED   %s: %s" % (f, why))
    for f, why in differ:
        print("DIFFERS %s: %s" % (f, why))
    print("%d files compared, %d differ" % (len((a_files | b_files)), len(differ)))
    return 1 if differ else 0


if __name__ == "__main__":
    args = sys.argv[1:]
    tol = 0.0
    if len(args) == 4 and args[0] == "--tolerance":
        tol, args = float(args[1]), args[2:]
    if len(args) != 2:
        sys.exit("usage: regression_compare.py [--tolerance REL] BEFORE AFTER")
    sys.exit(main(args[0], args[1], tol))
