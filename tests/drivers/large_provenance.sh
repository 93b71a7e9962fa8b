#!/bin/bash
# Provenance of any size (src/provenance.c): a 2.2 MB scene (the hanging sheet followed by 22,000 comment lines, the
# size of a scene with a 100,000-vertex DXF outline) and an option of 100 kB run on 2 ranks; the scene's bytes and the
# options are in /provenance of the series' NAME.h5 and of the checkpoint, exactly, and a restart reads the
# checkpoint. Both used to end at output set-up with exit 76 (H5Acreate2 fails for an attribute over 64 kB).
#
#   large_provenance.sh MPIEXEC
set -euo pipefail
mpiexec=$1
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
scene=$out/large.yaml
{ cat input/hanging_sheet.yaml; for i in $(seq -w 1 22000); do printf '# %s %090d\n' "$i" 0; done; } > "$scene"
note=$(head -c 100000 /dev/zero | tr '\0' n)
run() { "$mpiexec" -n 2 "$CLOTHSIM" -scene "$scene" -grid 9 -output_dir "$out/run" -provenance_note "$note" "$@" > "$out/log" 2>&1 || { tail -5 "$out/log" | cut -c1-300; fail "clothsim $* failed"; }; }
run -steps 3
run -steps 5 -restart "$out/run/checkpoint_000003.h5"
grep -q '^Done: 2 steps' "$out/log" || fail "the restart did not run steps 4 and 5"
/usr/bin/python3 - "$scene" "$out/run/hanging_sheet.h5" "$out/run/checkpoint_000003.h5" "$out/run/checkpoint_000005.h5" <<'PY'
import sys
import h5py
scene = open(sys.argv[1], "rb").read()
for path in sys.argv[2:]:
    with h5py.File(path, "r") as f:
        text, options = f["provenance/scene_text"][()], f["provenance/options"][()].decode()
    if text != scene or "-provenance_note " + "n" * 100000 not in options:
        sys.exit(f"FAIL: {path}: the scene text ({len(text)} bytes) or the options ({len(options)} characters) differ")
    print(f"{path}: scene text {len(text)} bytes, options {len(options)} characters, both exact")
PY
