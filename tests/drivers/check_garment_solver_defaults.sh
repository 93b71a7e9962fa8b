#!/bin/bash
# The implicit solve's defaults for garments (src/preconditioner.c, SetGarmentSolverDefaults): a scene with seams on
# point-block Jacobi stops CG on its natural norm at a relative decrease of 1e-4; -ksp_rtol and -ksp_norm_type
# override; a scene without seams keeps PETSc's (1e-5, the preconditioned norm). Read from -integrator_view's KSP.
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
  grep -E "tolerances:|norm type for convergence" "$dir/log" | head -2 | tr -s ' ' | tr '\n' ';'
}
garment=input/dress_fitted_coarse.yaml
sheet=input/hanging_sheet.yaml
out=$(view $garment)
[[ $out == *"relative=0.0001,"* && $out == *"NATURAL norm"* ]] || fail "garment default: $out (expected relative=0.0001, NATURAL norm)"
out=$(view $garment -ksp_rtol 1e-6 -ksp_norm_type preconditioned)
[[ $out == *"relative=1e-06,"* && $out == *"PRECONDITIONED norm"* ]] || fail "garment with -ksp_rtol 1e-6 -ksp_norm_type preconditioned: $out"
out=$(view $sheet -grid 9)
[[ $out == *"relative=1e-05,"* && $out == *"PRECONDITIONED norm"* ]] || fail "sheet default: $out (expected relative=1e-05, PRECONDITIONED norm)"
echo "PASS: garment rtol 1e-4 on the natural norm, overridden by options; the sheet keeps 1e-5 on the preconditioned norm"
