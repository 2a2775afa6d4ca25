#!/usr/bin/env bash
# python.soak under LeakSanitizer, reporting only what the plugin leaks.
#
#   cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DSOFTBODY_SANITIZER=address \
#         -DSOFTBODY_BUILD_TESTING=OFF -DSOFTBODY_BUILD_BENCHMARKS=OFF
#   cmake --build build-asan --target SoftBody
#   scripts/lsan_soak.sh [build-asan] [test_soak.py arguments...]
#
# pvpython itself leaks at exit (Python's interpreter state, VTK's Python type objects, Open
# MPI's initialisation, also in its orted helper process): ~3.3 MB in ~6,100 allocations, the
# same after 20 requests as after 400. A suppressions file cannot separate those from ours:
# LSan suppresses a leak when any frame of its stack matches, and every allocation our filter
# makes has Python frames below it. So the report is read instead: a leak is ours when a frame
# of its stack is in the plugin (SoftBody.so, vtkSoftBody*, softbody::, the readers and
# meshing filters). Exit status: 1 when the soak failed or the plugin leaked, else 0.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build-asan}"
shift || true
plugin="$build/lib/paraview-5.11/plugins/SoftBody/SoftBody.so"
logs="$(mktemp -d)"
asan_lib="$(g++ -print-file-name=libasan.so)"

status=0
LD_PRELOAD="$asan_lib" \
ASAN_OPTIONS="detect_leaks=1:detect_odr_violation=0:alloc_dealloc_mismatch=0:log_path=$logs/lsan" \
  pvpython "$here/tests/python/test_soak.py" --plugin "$plugin" --data-dir "$here/data" \
  --rss-bound-mib 4096 "$@" > "$logs/soak.log" 2>&1 || status=$?
# Under ASan VmRSS includes the allocator's quarantine: the RSS bound is not checked here.
tail -n 3 "$logs/soak.log"
if ! grep -q "^python.soak passed" "$logs/soak.log"; then
  echo "the soak itself failed (exit $status): $logs/soak.log"
  exit 1
fi
python3 - "$logs" <<'EOF'
import glob, re, sys
ours_pattern = re.compile(r"SoftBody\.so|vtkSoftBody|softbody::|vtkTetGenReader|vtkGmshReader|"
                          r"vtkTetrahedralizeSurface")
total = ours = records = 0
for path in glob.glob(sys.argv[1] + "/lsan.*"):
    for record in re.split(r"\n(?=(?:Direct|Indirect) leak of)", open(path).read()):
        match = re.match(r"(?:Direct|Indirect) leak of (\d+) byte", record)
        if not match:
            continue
        records += 1
        total += int(match.group(1))
        if ours_pattern.search(record):
            ours += int(match.group(1))
            print(record.strip()[:4000], "\n")
print(f"LeakSanitizer: {total} bytes in {records} leak records in all (pvpython, Python, Open MPI); "
      f"{ours} bytes with a frame of the plugin. Reports: {sys.argv[1]}")
sys.exit(1 if ours else 0)
EOF
