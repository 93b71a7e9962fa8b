#!/bin/bash
# The implicit solve's defaults for garments (src/implicit_solver.c, SetGarmentDefaults): a scene with seams on
# point-block Jacobi stops CG on its natural norm at a relative decrease of 1e-4; -ksp_rtol and -ksp_norm_type
# override; a scene without seams keeps PETSc's (1e-5, the preconditioned norm). Read from -integrator_view's KSP.
# The garment's preconditioner is seam-block Jacobi (src/seam_blocks.c; -implicit_pc_seam_blocks false: point-block
# Jacobi), and over the main job's first 100 steps on 2 ranks it takes at most 0.85 times point-block Jacobi's Krylov
# iterations and at most 160 a step (measured 14,026 against 18,141: 0.77, 140 a step; over 300 steps 0.74).
#
#   check_garment_solver_defaults.sh MPIEXEC DIR
set -euo pipefail
mpiexec=$1 dir=$2
: "${CLOTHSIM:?set CLOTHSIM to the clothsim binary}"
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*"; exit 1; }
view() { # SCENE OPTION...: the KSP's tolerances and norm lines of a 2-step run
  local scene=$1
  shift
  "$mpiexec" -n 2 "$CLOTHSIM" -scene "$scene" -steps 2 -output_every 0 -output_dir "$dir/run" -output_overwrite -integrator_view "$@" > "$dir/log" 2>&1 ||
    { cat "$dir/log"; fail "clothsim -scene $scene $* failed"; }
  grep -E "tolerances:|norm type for convergence|Seam-block Jacobi:|type: pbjacobi" "$dir/log" | head -3 | tr -s ' ' | tr '\n' ';'
}
iterations() { # OPTION...: Krylov iterations of the main job's first 100 steps on 2 ranks
  "$mpiexec" -n 2 "$CLOTHSIM" -scene input/dress_fitted_coarse.yaml -cloth_stiffness gauss_newton -steps 100 -output_every 0 -output_dir "$dir/run" -output_overwrite "$@" > "$dir/log" 2>&1 ||
    { cat "$dir/log"; fail "the main job's first 100 steps with $* failed"; }
  sed -n 's/^Done: 100 steps (100 sub-steps), \([0-9]*\) Krylov iterations.*/\1/p' "$dir/log"
}
garment=input/dress_fitted_coarse.yaml
sheet=input/hanging_sheet.yaml
out=$(view $garment)
[[ $out == *"relative=0.0001,"* && $out == *"NATURAL norm"* && $out == *"Seam-block Jacobi:"* ]] || fail "garment default: $out (expected relative=0.0001, NATURAL norm, seam-block Jacobi)"
out=$(view $garment -implicit_pc_seam_blocks false)
[[ $out == *"relative=0.0001,"* && $out == *"type: pbjacobi"* ]] || fail "garment with -implicit_pc_seam_blocks false: $out (expected relative=0.0001, point-block Jacobi)"
out=$(view $garment -ksp_rtol 1e-6 -ksp_norm_type preconditioned)
[[ $out == *"relative=1e-06,"* && $out == *"PRECONDITIONED norm"* ]] || fail "garment with -ksp_rtol 1e-6 -ksp_norm_type preconditioned: $out"
out=$(view $sheet -grid 9)
[[ $out == *"relative=1e-05,"* && $out == *"PRECONDITIONED norm"* ]] || fail "sheet default: $out (expected relative=1e-05, PRECONDITIONED norm)"
seam=$(iterations)
point=$(iterations -implicit_pc_seam_blocks false)
[[ -n $seam && -n $point ]] || fail "no Krylov iteration count in a run's Done line"
echo "main job, 100 steps: seam-block Jacobi $seam, point-block Jacobi $point Krylov iterations"
((100 * seam <= 85 * point)) || fail "seam-block Jacobi took $seam iterations, more than 0.85 x point-block Jacobi's $point"
((seam <= 16000)) || fail "seam-block Jacobi took $seam iterations, more than 160 a step"
echo "PASS: garment rtol 1e-4 on the natural norm with seam-block Jacobi, overridden by options; the sheet keeps 1e-5 on the preconditioned norm; seam blocks save Krylov iterations"
