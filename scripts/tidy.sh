#!/usr/bin/env bash
# clang-tidy over the tree with the checks in .clang-tidy (every finding an error).
#   bash scripts/tidy.sh              every source file of core/, plugins/, apps/, experiments/, tests/
#   bash scripts/tidy.sh FILE.cc ...  those files only
# Configures build-tidy/ (the `tidy` preset: clang's flags), builds its precompiled headers only
# (Eigen, Ceres, GoogleTest: clang-tidy reads them instead of parsing them for every file) and
# reads its compile_commands.json. About 5 s a file on one core.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset tidy > /dev/null
mapfile -t headers < <(ninja -C build-tidy -t targets all | sed -n 's/^\([^:]*\.pch\):.*/\1/p')
ninja -C build-tidy "${headers[@]}" > /dev/null
jobs=$(nproc)
if [ $# -gt 0 ]; then
  files=("$@")
else
  mapfile -t files < <(git ls-files 'core/*.cc' 'plugins/*.cc' 'apps/*.cc' 'experiments/*.cc' 'tests/*.cc')
fi
# Only files the tidy tree compiles (the asan-only and fuzz sources are not in it).
mapfile -t known < <(python3 -c '
import json, os, sys
listed = {os.path.realpath(e["file"]) for e in json.load(open("build-tidy/compile_commands.json"))}
for f in sys.argv[1:]:
    if os.path.realpath(f) in listed: print(f)
' "${files[@]}")
echo "clang-tidy: ${#known[@]} files, $jobs at a time"
printf '%s\n' "${known[@]}" |
  xargs -P "$jobs" -n 1 clang-tidy-14 -p build-tidy --quiet 2> >(grep -v "warnings generated" >&2)
echo "clang-tidy: no findings"
