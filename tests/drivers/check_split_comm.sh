#!/bin/bash
# Two simulations side by side on the two halves of MPI_COMM_WORLD (tests/programs/test_split_comm.c, 2 ranks: one each)
# give, each, the answer of the same run alone on one rank, bit for bit: the hanging sheet (17 x 17, 40 steps,
# implicit) in one half and the sphere drape (17 x 17, 40 steps, contacts) in the other, so that a collective on the
# wrong communicator would hang or mix the two.
# Usage: check_split_comm.sh MPIEXEC WORKDIR      (SPLIT: build/tests/test_split_comm, CLOTHSIM: the binary)
set -euo pipefail
mpiexec=$1 work=$2
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"
mkdir -p "$work"
# One scene per half: the options database is per process, so each rank of the split run reads its own -scene.
cat > "$work/app.sh" <<APP
#!/bin/bash
if [ "\${OMPI_COMM_WORLD_RANK:-0}" = 0 ]; then scene=input/hanging_sheet.yaml; else scene=input/sphere_drape.yaml; fi
exec "$SPLIT" -scene "\$scene" -grid 17 -steps 40 -output_every 0 -progress_seconds 100 -output_dir_0 "$work/half0" -output_dir_1 "$work/half1"
APP
chmod +x "$work/app.sh"
timeout 120 "$mpiexec" -n 2 "$work/app.sh" > "$work/split.log" 2>&1 || { cat "$work/split.log"; fail "the split run failed or hung"; }
for pair in "hanging_sheet half0" "sphere_drape half1"; do
  set -- $pair
  "$mpiexec" -n 1 "$CLOTHSIM" -scene "input/$1.yaml" -grid 17 -steps 40 -output_every 0 -progress_seconds 100 -output_dir "$work/alone_$1" > "$work/alone_$1.log" 2>&1 ||
    { cat "$work/alone_$1.log"; fail "$1 alone failed"; }
  /usr/bin/python3 tests/checkers/compare_checkpoints.py "$work/$2/checkpoint_000040.h5" "$work/alone_$1/checkpoint_000040.h5" --tolerance 0 ||
    fail "$1 in half of MPI_COMM_WORLD differs from $1 alone"
done
