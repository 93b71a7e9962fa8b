#!/bin/bash
# A checkpoint whose string attribute claims 2 MB (/state/integrator as a 2,000,000-byte string, in HDF5's dense
# attribute storage) is refused as corrupt (src/h5util.c, ClothH5AttributeReadString: at most 1 MB, since clothsim
# writes only names and paths there), before the reader allocates what the file claims: a damaged datatype may claim
# gigabytes (issue 48's sweep of allocations sized from input). Before, it was read and the run went on.
#
#   checkpoint_huge_attribute.sh RANKS
set -euo pipefail
tests=$(cd "$(dirname "$0")/.." && pwd)
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
mpiexec=${MPIEXEC:-mpiexec}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$mpiexec" -n "$1" "$CLOTHSIM" -scene input/hanging_sheet.yaml -grid 9 -steps 2 -output_dir "$out/run" > "$out/log" 2>&1 || { tail "$out/log"; echo "FAIL: the first run failed"; exit 1; }
/usr/bin/python3 - "$out/run/checkpoint_000002.h5" "$out/huge_attribute.h5" <<'PY'
import sys
import h5py
with h5py.File(sys.argv[1], "r") as src, h5py.File(sys.argv[2], "w", libver="latest") as dst:
    gcpl = h5py.h5p.create(h5py.h5p.GROUP_CREATE)
    gcpl.set_attr_phase_change(0, 0)  # dense attribute storage: attributes beyond the header's 64 kB
    h5py.h5g.create(dst.id, b"state", gcpl=gcpl)
    for key, value in src["state"].attrs.items():
        if key == "integrator":
            dst["state"].attrs.create(key, b"implicit", dtype="S2000000")
        else:
            dst["state"].attrs[key] = value
    for name in src["state"]:
        src.copy(src["state"][name], dst["state"], name)
PY
bash "$tests/drivers/expect_error.sh" --status 3 "$1" input/hanging_sheet.yaml "Checkpoint $out/huge_attribute.h5 is corrupt: it cannot be read (HDF5 attribute integrator is a string of 2000000 bytes: expected at most 1048576" \
  -- -grid 9 -steps 3 -restart "$out/huge_attribute.h5" -output_dir "$out/run"
