#!/usr/bin/env bash
# A restart with the cloth held on a mesh body (the mannequin): the sheet of tests/data/mannequin_shoulder.yaml
# on 2 ranks, 120 steps against 60 + restart + 60. Held mesh contacts need the triangle they are held on, which
# the checkpoint does not store; ClothCollisionRestoreHeldContacts finds it again from the contact normal (a
# face normal, bit for bit; the contact's anchor is that triangle's first vertex). The final states must be
# bit-identical (measured: they are; a landing sheet turns any round-off difference into millimetres within a
# few steps). Before: the dress's restart jumped from 1e-5 J to 4.8e-3 J of kinetic energy.
#   bash tests/drivers/restart_mesh_contacts.sh        (CLOTHSIM: the binary)
set -euo pipefail
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
tests=$(cd "$(dirname "$0")/.." && pwd)
common=(-scene "$tests/data/mannequin_shoulder.yaml" -output_every 0 -progress_seconds 100)
mpiexec -n 2 "$CLOTHSIM" "${common[@]}" -steps 120 -output_dir "$out/full" > "$out/full.log" 2>&1 || { tail -20 "$out/full.log"; exit 1; }
mpiexec -n 2 "$CLOTHSIM" "${common[@]}" -steps 60 -output_dir "$out/split" > "$out/first.log" 2>&1 || { tail -20 "$out/first.log"; exit 1; }
mpiexec -n 2 "$CLOTHSIM" "${common[@]}" -steps 120 -output_dir "$out/split" -restart "$out/split/checkpoint_000060.h5" -info :sys > "$out/second.log" 2>&1 || { tail -20 "$out/second.log"; exit 1; }
grep -h "Restored .* held mesh contacts" "$out/second.log" | sed 's/^\[[0-9]*\] *[A-Za-z]*(): //' || { echo "FAIL: no held contacts restored"; exit 1; }
/usr/bin/python3 - "$out/split/checkpoint_000060.h5" <<'PY'
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    c = f["state/contact_normal"][...]
n = np.linalg.norm(c, axis=1)
print(f"at the restart: {(n > 0).sum()} particles held on the mannequin, {(n > 1.5).sum()} of them stuck")
sys.exit(0 if (n > 0).sum() >= 5 else "FAIL: fewer than 5 held particles at the restart")
PY
/usr/bin/python3 "$tests/checkers/compare_restart.py" "$out/full/checkpoint_000120.h5" "$out/split/checkpoint_000120.h5"
