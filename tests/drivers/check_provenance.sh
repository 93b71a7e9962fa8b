#!/bin/bash
# Provenance in every HDF5 file a run writes (src/provenance.c): the series' NAME.h5 (root attributes) and the
# checkpoint (/state attributes) carry the scene file's path, the code version and the git revision the binary was
# built from (the one the build wrote into generated/clothsim_revision.h); both carry the scene file's bytes exactly
# and the run's options as the datasets /provenance/scene_text and /provenance/options.
# The run's identity (run_id) is the same in the series' .h5, the checkpoint, a comment of NAME.xdmf (which stays
# valid XML: xmllint) and, for a scene with seams (tests/data/seam_two_pieces.yaml), quality.json.
# Usage: check_provenance.sh MPIEXEC WORKDIR      (CLOTHSIM: the binary, CLOTHSIM_BUILD: its build directory)
set -euo pipefail
mpiexec=$1 work=$2
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"
"$mpiexec" -n 2 "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 9 -steps 3 -output_dir "$work" > "$work.log" 2>&1 || { cat "$work.log"; fail "run failed"; }
revision=$(sed -n 's/^#define CLOTHSIM_GIT_REVISION "\(.*\)"$/\1/p' "$CLOTHSIM_BUILD/generated/clothsim_revision.h")
[ -n "$revision" ] || fail "no revision in $CLOTHSIM_BUILD/generated/clothsim_revision.h"
/usr/bin/python3 - "$work/hanging_sheet.h5" "$work/checkpoint_000003.h5" input/hanging_sheet.yaml "$revision" <<'PY'
import sys
import h5py
series, checkpoint, scene, revision = sys.argv[1:5]
text = open(scene, "rb").read().decode()
for path, group in ((series, "/"), (checkpoint, "/state")):
    f = h5py.File(path, "r")
    attrs = {k: (v.decode() if isinstance(v, bytes) else str(v)) for k, v in f[group].attrs.items()}
    texts = {k: f["provenance"][k][()].decode() for k in ("scene_text", "options") if k in f.get("provenance", {})}
    checks = {"scene_text": texts.get("scene_text") == text, "scene_path": attrs.get("scene_path") == scene,
              "git_revision": attrs.get("git_revision") == revision, "code_version": bool(attrs.get("code_version")),
              "options": "-grid 9" in texts.get("options", "") and "-steps 3" in texts.get("options", "")}
    bad = [k for k, ok in checks.items() if not ok]
    if bad:
        sys.exit(f"FAIL: {path}{group}: {bad} wrong or missing")
    print(f"{path}: scene ({len(text)} bytes), options, code {attrs['code_version']}, revision {attrs['git_revision']}")
PY

"$mpiexec" -n 2 "$CLOTHSIM" -scene tests/data/seam_two_pieces.yaml -steps 10 -output_dir "$work/seams" > "$work.log" 2>&1 || { cat "$work.log"; fail "run with seams failed"; }
for dir in "$work" "$work/seams"; do
  xdmf=$(ls "$dir"/*.xdmf)
  xmllint --noout "$xdmf" || fail "$xdmf is not valid XML"
  /usr/bin/python3 - "$dir" <<'PY'
import glob, json, os, re, sys
import h5py
d = sys.argv[1]
name = os.path.basename(glob.glob(d + "/*.xdmf")[0])[:-5]
ids = {"series": "%016x" % h5py.File(f"{d}/{name}.h5", "r").attrs["run_id"],
       "checkpoint": "%016x" % h5py.File(sorted(glob.glob(d + "/checkpoint_*.h5"))[-1], "r")["/state"].attrs["run_id"]}
m = re.search(r"<!-- run_id ([0-9a-f]{16}):", open(f"{d}/{name}.xdmf").read())
ids["xdmf"] = m.group(1) if m else None
if os.path.exists(d + "/quality.json") or name == "seam_two_pieces":
    ids["quality.json"] = json.load(open(d + "/quality.json")).get("run_id")
if len(set(ids.values())) != 1:
    sys.exit(f"FAIL: {d}: run_id differs or is missing: {ids}")
print(f"{name}: run_id {ids['series']} in {', '.join(ids)}")
PY
done
